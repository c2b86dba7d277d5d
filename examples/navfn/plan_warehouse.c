/* Plans across the bundled warehouse map through vouch's C ABI and checks the plan.
 *   cc -std=c99 -Icrates/vouch-navfn-capi/include examples/navfn/plan_warehouse.c \
 *      -Ltarget/release -lvouch_navfn_c -Wl,-rpath,$PWD/target/release -o plan_warehouse
 *   ./plan_warehouse examples/navfn/warehouse.yaml
 */
#include <stdio.h>
#include <stdlib.h>

#include "vouch_navfn.h"

int main(int argc, char **argv) {
  const char *map = argc > 1 ? argv[1] : "examples/navfn/warehouse.yaml";
  VouchNavfnParams params = vouch_navfn_default_params();
  params.use_final_approach_orientation = true;
  VouchNavfnPlanner *planner = NULL;
  if (vouch_navfn_planner_from_map(map, &params, &planner) != VOUCH_NAVFN_STATUS_OK) {
    fprintf(stderr, "%s\n", vouch_navfn_last_error());
    return 1;
  }
  VouchNavfnPose start = {1.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0};
  VouchNavfnPose goal = {8.5, 6.5, 0.0, 0.0, 0.0, 0.0, 1.0};
  size_t n = 0, violations = 0;
  if (vouch_navfn_plan_world(planner, &start, &goal, &n) != VOUCH_NAVFN_STATUS_OK) {
    fprintf(stderr, "%s\n", vouch_navfn_last_error());
    vouch_navfn_planner_free(planner);
    return 1;
  }
  VouchNavfnPose *poses = malloc(n * sizeof *poses);
  vouch_navfn_get_poses(planner, poses, n, &n);
  vouch_navfn_check(planner, &violations);
  printf("%zu poses, last (%.3f, %.3f) facing qz=%.4f qw=%.4f, %zu violations\n", n,
         poses[n - 1].x, poses[n - 1].y, poses[n - 1].qz, poses[n - 1].qw, violations);
  free(poses);
  vouch_navfn_planner_free(planner);
  return violations == 0 ? 0 : 3;
}
