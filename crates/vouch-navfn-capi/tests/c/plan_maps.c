/* A C program using vouch_navfn.h the way a nav2 user would, for the integration test.
 *
 *   plan_maps bin MAP.bin W H ORIGIN_X ORIGIN_Y RES   < cases   (ROS costmap bytes)
 *   plan_maps yaml MAP.yaml                           < cases   (map_server map)
 *   plan_maps navfn MAP.bin W H                       < cell cases (NavFn costs)
 *   plan_maps errors
 *
 * Cases are lines "x0 y0 x1 y1" in metres. "bin" prints the golden line format's facts:
 * CASE k status=S len=N pot_fnv=H, PATH (float bits), WORLD (double bits), CHECK n.
 * "yaml" prints POSES n, then "x y qz qw" per pose (%.17g), CHECK n.
 */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "vouch_navfn.h"

static uint64_t fnv(const unsigned char *p, size_t n, uint64_t h) {
  for (size_t i = 0; i < n; i++) {
    h ^= p[i];
    h *= 0x100000001b3ULL;
  }
  return h;
}

static const char *status_name(VouchNavfnPlanStatus s) {
  switch (s) {
    case VOUCH_NAVFN_PLAN_STATUS_FOUND: return "OK";
    case VOUCH_NAVFN_PLAN_STATUS_NO_VALID_PATH_COULD_BE_FOUND: return "NoValidPathCouldBeFound";
    case VOUCH_NAVFN_PLAN_STATUS_START_OUTSIDE_MAP_BOUNDS: return "StartOutsideMapBounds";
    case VOUCH_NAVFN_PLAN_STATUS_GOAL_OUTSIDE_MAP_BOUNDS: return "GoalOutsideMapBounds";
    case VOUCH_NAVFN_PLAN_STATUS_GOAL_OCCUPIED: return "GoalOccupied";
    case VOUCH_NAVFN_PLAN_STATUS_START_EQUALS_GOAL: return "StartEqualsGoal";
    case VOUCH_NAVFN_PLAN_STATUS_UB_START_ROUNDS_OUT_OF_MAP: return "UB_StartRoundsOutOfMap";
    case VOUCH_NAVFN_PLAN_STATUS_UB_GOAL_ROUNDS_OUT_OF_MAP: return "UB_GoalRoundsOutOfMap";
  }
  return "?";
}

static uint64_t bits64(double d) { uint64_t u; memcpy(&u, &d, 8); return u; }
static uint32_t bits32(float f) { uint32_t u; memcpy(&u, &f, 4); return u; }

static VouchNavfnPose at(double x, double y) {
  VouchNavfnPose p = {x, y, 0.0, 0.0, 0.0, 0.0, 1.0};
  return p;
}

static int fail(const char *what, VouchNavfnStatus s) {
  fprintf(stderr, "%s: status %d: %s\n", what, (int)s, vouch_navfn_last_error());
  return 1;
}

/* One plan in the golden format's terms. */
static int plan_bin(VouchNavfnPlanner *pl, int k, VouchNavfnPose s, VouchNavfnPose g) {
  size_t n = 0, w = 0, h = 0;
  VouchNavfnStatus st = vouch_navfn_plan_world(pl, &s, &g, &n);
  if (st != VOUCH_NAVFN_STATUS_OK && st != VOUCH_NAVFN_STATUS_NO_PLAN) return fail("plan", st);
  VouchNavfnPlanStatus ps;
  vouch_navfn_plan_status(pl, &ps);
  vouch_navfn_size(pl, &w, &h);
  size_t npath = 0;
  /* a NULL buffer asks for the count */
  st = vouch_navfn_get_navfn_path(pl, NULL, 0, &npath);
  if (st != VOUCH_NAVFN_STATUS_OK) return fail("count of the path", st);
  if (vouch_navfn_get_navfn_path(pl, NULL, 0, NULL) != VOUCH_NAVFN_STATUS_NULL_ARGUMENT && npath > 0)
    return fail("no buffer and no count", st);
  float *path = malloc(2 * (npath ? npath : 1) * sizeof(float));
  vouch_navfn_get_navfn_path(pl, path, npath, &npath);
  uint64_t pot_fnv = 0xcbf29ce484222325ULL;
  float *pot = malloc(w * h * sizeof(float));
  size_t npot = 0;
  if (vouch_navfn_get_potential(pl, pot, w * h, &npot) == VOUCH_NAVFN_STATUS_OK)
    pot_fnv = fnv((const unsigned char *)pot, npot * sizeof(float), pot_fnv);
  printf("CASE %d status=%s len=%zu pot_fnv=%016llx\n", k, status_name(ps),
         ps == VOUCH_NAVFN_PLAN_STATUS_FOUND ? npath : (size_t)0, (unsigned long long)pot_fnv);
  printf("PATH");
  for (size_t i = 0; ps == VOUCH_NAVFN_PLAN_STATUS_FOUND && i < npath; i++)
    printf(" %08x:%08x", bits32(path[2 * i]), bits32(path[2 * i + 1]));
  printf("\nWORLD");
  VouchNavfnPose *poses = malloc((n ? n : 1) * sizeof(VouchNavfnPose));
  vouch_navfn_get_poses(pl, poses, n, &n);
  for (size_t i = 0; i < n; i++)
    printf(" %016llx:%016llx", (unsigned long long)bits64(poses[i].x),
           (unsigned long long)bits64(poses[i].y));
  size_t violations = 0;
  if (vouch_navfn_check(pl, &violations) == VOUCH_NAVFN_STATUS_NO_RESULT) violations = 0;
  printf("\nCHECK %zu\n", violations);
  free(path);
  free(pot);
  free(poses);
  return 0;
}

static int run_cases(VouchNavfnPlanner *pl, int yaml) {
  double x0, y0, x1, y1;
  int k = 0;
  while (scanf("%lf %lf %lf %lf", &x0, &y0, &x1, &y1) == 4) {
    if (!yaml) {
      if (plan_bin(pl, k++, at(x0, y0), at(x1, y1))) return 1;
      continue;
    }
    VouchNavfnPose s = at(x0, y0), g = at(x1, y1);
    g.qz = 0.6; g.qw = 0.8; /* a goal heading: the last pose carries it */
    size_t n = 0, violations = 0;
    VouchNavfnStatus st = vouch_navfn_plan_world(pl, &s, &g, &n);
    if (st != VOUCH_NAVFN_STATUS_OK && st != VOUCH_NAVFN_STATUS_NO_PLAN) return fail("plan", st);
    VouchNavfnPose *poses = malloc((n ? n : 1) * sizeof(VouchNavfnPose));
    vouch_navfn_get_poses(pl, poses, n, &n);
    printf("POSES %zu\n", n);
    for (size_t i = 0; i < n; i++)
      printf("%.17g %.17g %.17g %.17g\n", poses[i].x, poses[i].y, poses[i].qz, poses[i].qw);
    if (vouch_navfn_check(pl, &violations) == VOUCH_NAVFN_STATUS_NO_RESULT) violations = 0;
    printf("CHECK %zu\n", violations);
    free(poses);
  }
  return 0;
}

/* Cell plans on NavFn costs: the planner's cell-level call sequence. */
static int run_cells(VouchNavfnPlanner *pl, size_t w, size_t h) {
  unsigned x0, y0, x1, y1;
  int k = 0;
  float *pot = malloc(w * h * sizeof(float));
  while (scanf("%u %u %u %u", &x0, &y0, &x1, &y1) == 4) {
    size_t n = 0, npath = 0, npot = 0;
    VouchNavfnStatus st = vouch_navfn_plan_cells(pl, x0, y0, x1, y1, &n);
    if (st != VOUCH_NAVFN_STATUS_OK && st != VOUCH_NAVFN_STATUS_NO_PLAN) return fail("plan_cells", st);
    vouch_navfn_get_navfn_path(pl, NULL, 0, &npath);
    float *path = malloc(2 * (npath ? npath : 1) * sizeof(float));
    vouch_navfn_get_navfn_path(pl, path, npath, &npath);
    vouch_navfn_get_potential(pl, pot, w * h, &npot);
    uint64_t h64 = fnv((const unsigned char *)pot, npot * sizeof(float), 0xcbf29ce484222325ULL);
    printf("CASE %d len=%zu pot_fnv=%016llx\nPATH", k++, npath, (unsigned long long)h64);
    for (size_t i = 0; i < npath; i++)
      printf(" %08x:%08x", bits32(path[2 * i]), bits32(path[2 * i + 1]));
    printf("\n");
    free(path);
  }
  free(pot);
  return 0;
}

/* Every error comes back as a code and a message; nothing crashes. */
static int errors(void) {
  VouchNavfnPlanner *pl = NULL;
  uint8_t costs[9] = {0};
  VouchNavfnParams params = vouch_navfn_default_params();
  VouchNavfnStatus s = vouch_navfn_planner_new(NULL, 3, 3, VOUCH_NAVFN_COST_KIND_ROS, 0, 0, 1, NULL, &pl);
  printf("null_costs %d %s\n", (int)s, vouch_navfn_last_error());
  s = vouch_navfn_planner_new(costs, 3, 3, VOUCH_NAVFN_COST_KIND_ROS, 0, 0, -1, NULL, &pl);
  printf("bad_resolution %d %s\n", (int)s, vouch_navfn_last_error());
  params.tolerance = -1;
  s = vouch_navfn_planner_new(costs, 3, 3, VOUCH_NAVFN_COST_KIND_ROS, 0, 0, 1, &params, &pl);
  printf("bad_tolerance %d %s\n", (int)s, vouch_navfn_last_error());
  s = vouch_navfn_planner_from_map("no/such/map.yaml", NULL, &pl);
  printf("missing_map %d %s\n", (int)s, vouch_navfn_last_error());
  s = vouch_navfn_planner_new(costs, 3, 3, VOUCH_NAVFN_COST_KIND_NAVFN, 0, 0, 1, NULL, &pl);
  printf("created %d\n", (int)s);
  size_t n = 0;
  VouchNavfnPose p = at(1, 1);
  s = vouch_navfn_plan_world(pl, &p, &p, &n);
  printf("world_on_navfn_costs %d %s\n", (int)s, vouch_navfn_last_error());
  s = vouch_navfn_plan_cells(pl, 0, 0, 7, 7, &n);
  printf("cell_off_map %d %s\n", (int)s, vouch_navfn_last_error());
  s = vouch_navfn_get_poses(pl, NULL, 0, &n);
  printf("no_result %d %s\n", (int)s, vouch_navfn_last_error());
  s = vouch_navfn_plan_world(NULL, &p, &p, &n);
  printf("null_planner %d %s\n", (int)s, vouch_navfn_last_error());
  s = vouch_navfn_set_costmap(pl, costs, 4, VOUCH_NAVFN_COST_KIND_ROS);
  printf("short_costmap %d %s\n", (int)s, vouch_navfn_last_error());
  vouch_navfn_planner_free(pl);
  vouch_navfn_planner_free(NULL);
  return 0;
}

int main(int argc, char **argv) {
  if (argc >= 2 && strcmp(argv[1], "errors") == 0) return errors();
  VouchNavfnPlanner *pl = NULL;
  VouchNavfnStatus s;
  if (argc == 8 && strcmp(argv[1], "bin") == 0) {
    size_t w = strtoul(argv[3], NULL, 10), h = strtoul(argv[4], NULL, 10);
    uint8_t *costs = malloc(w * h);
    FILE *f = fopen(argv[2], "rb");
    if (!f || fread(costs, 1, w * h, f) != w * h) { fprintf(stderr, "cannot read %s\n", argv[2]); return 1; }
    fclose(f);
    s = vouch_navfn_planner_new(costs, w, h, VOUCH_NAVFN_COST_KIND_ROS, atof(argv[5]), atof(argv[6]),
                                atof(argv[7]), NULL, &pl);
    free(costs);
    if (s != VOUCH_NAVFN_STATUS_OK) return fail("planner_new", s);
    int r = run_cases(pl, 0);
    vouch_navfn_planner_free(pl);
    return r;
  }
  if (argc == 5 && strcmp(argv[1], "navfn") == 0) {
    size_t w = strtoul(argv[3], NULL, 10), h = strtoul(argv[4], NULL, 10);
    uint8_t *costs = malloc(w * h);
    FILE *f = fopen(argv[2], "rb");
    if (!f || fread(costs, 1, w * h, f) != w * h) { fprintf(stderr, "cannot read %s\n", argv[2]); return 1; }
    fclose(f);
    s = vouch_navfn_planner_new(costs, w, h, VOUCH_NAVFN_COST_KIND_NAVFN, 0, 0, 1, NULL, &pl);
    free(costs);
    if (s != VOUCH_NAVFN_STATUS_OK) return fail("planner_new", s);
    int r = run_cells(pl, w, h);
    vouch_navfn_planner_free(pl);
    return r;
  }
  if (argc == 3 && strcmp(argv[1], "yaml") == 0) {
    s = vouch_navfn_planner_from_map(argv[2], NULL, &pl);
    if (s != VOUCH_NAVFN_STATUS_OK) return fail("planner_from_map", s);
    int r = run_cases(pl, 1);
    vouch_navfn_planner_free(pl);
    return r;
  }
  fprintf(stderr, "usage: plan_maps bin MAP W H OX OY RES | yaml MAP.yaml | navfn MAP W H | errors\n");
  return 2;
}
