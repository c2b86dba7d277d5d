/* A C program using the inflation and body check of vouch_navfn.h, for the integration test.
 *
 *   costmap_body inflate MAP.bin W H RES ROBOT OUT.bin INFLATION_RADIUS K UNKNOWN AROUND PADDING
 *   costmap_body body MAP.bin W H ORIGIN_X ORIGIN_Y RES ROBOT WINDOW   < poses ("x y yaw" lines)
 *   costmap_body errors
 *
 * ROBOT is a footprint string when it starts with '[', else a robot radius. MAP.bin holds the
 * W·H static layer bytes (Costmap2D values, row 0 = bottom). "inflate" writes the inflated bytes
 * to OUT.bin. "body" prints one BODY line (the report, doubles as %.17g) and a CONTACT line per
 * contact. "errors" prints one "name status message" line per bad call.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "vouch_navfn.h"

static unsigned char *read_bin(const char *path, size_t n) {
  FILE *f = fopen(path, "rb");
  if (!f) return NULL;
  unsigned char *buf = malloc(n ? n : 1);
  size_t got = buf ? fread(buf, 1, n, f) : 0;
  fclose(f);
  if (got != n) {
    free(buf);
    return NULL;
  }
  return buf;
}

/* The robot argument: a footprint string, or a radius (footprint NULL). */
static void robot(const char *arg, double *radius, const char **footprint) {
  *radius = 0.0;
  *footprint = NULL;
  if (arg[0] == '[') *footprint = arg;
  else *radius = strtod(arg, NULL);
}

static int inflate(char **argv) {
  size_t w = strtoul(argv[3], NULL, 10), h = strtoul(argv[4], NULL, 10);
  unsigned char *map = read_bin(argv[2], w * h);
  if (!map) return 2;
  double radius;
  const char *footprint;
  robot(argv[6], &radius, &footprint);
  VouchNavfnInflationParams p = vouch_navfn_default_inflation_params();
  p.inflation_radius = strtod(argv[8], NULL);
  p.cost_scaling_factor = strtod(argv[9], NULL);
  p.inflate_unknown = atoi(argv[10]) != 0;
  p.inflate_around_unknown = atoi(argv[11]) != 0;
  p.footprint_padding = strtod(argv[12], NULL);
  /* in place: the output buffer is the input */
  VouchNavfnStatus s =
      vouch_navfn_inflate(map, w * h, w, h, strtod(argv[5], NULL), radius, footprint, &p, map, w * h);
  if (s != VOUCH_NAVFN_STATUS_OK) {
    fprintf(stderr, "inflate: status %d: %s\n", (int)s, vouch_navfn_last_error());
    free(map);
    return 1;
  }
  FILE *out = fopen(argv[7], "wb");
  int ok = out && fwrite(map, 1, w * h, out) == w * h;
  if (out) fclose(out);
  free(map);
  return ok ? 0 : 2;
}

static int body(char **argv) {
  size_t w = strtoul(argv[3], NULL, 10), h = strtoul(argv[4], NULL, 10);
  unsigned char *map = read_bin(argv[2], w * h);
  if (!map) return 2;
  double radius;
  const char *footprint;
  robot(argv[8], &radius, &footprint);
  size_t n = 0, cap = 16;
  double *x = malloc(cap * sizeof *x), *y = malloc(cap * sizeof *y), *yaw = malloc(cap * sizeof *yaw);
  double a, b, c;
  while (scanf("%lf %lf %lf", &a, &b, &c) == 3) {
    if (n == cap) {
      cap *= 2;
      x = realloc(x, cap * sizeof *x);
      y = realloc(y, cap * sizeof *y);
      yaw = realloc(yaw, cap * sizeof *yaw);
    }
    x[n] = a;
    y[n] = b;
    yaw[n] = c;
    n++;
  }
  VouchNavfnBodyReport r;
  /* first the count, then the contacts */
  VouchNavfnStatus s = vouch_navfn_check_body(map, w * h, w, h, strtod(argv[5], NULL),
                                              strtod(argv[6], NULL), strtod(argv[7], NULL), radius,
                                              footprint, x, y, yaw, n, strtod(argv[9], NULL), &r,
                                              NULL, 0);
  VouchNavfnClearance *contacts = malloc((r.contacts ? r.contacts : 1) * sizeof *contacts);
  if (s == VOUCH_NAVFN_STATUS_OK)
    s = vouch_navfn_check_body(map, w * h, w, h, strtod(argv[5], NULL), strtod(argv[6], NULL),
                               strtod(argv[7], NULL), radius, footprint, x, y, yaw, n,
                               strtod(argv[9], NULL), &r, contacts, r.contacts);
  if (s != VOUCH_NAVFN_STATUS_OK) {
    fprintf(stderr, "body: status %d: %s\n", (int)s, vouch_navfn_last_error());
    return 1;
  }
  printf("BODY ok=%d contacts=%zu motions=%zu has_min=%d clearance=%.17g pose=%zu cell=%zu,%zu "
         "at=%.17g,%.17g window=%.17g\n",
         (int)r.ok, r.contacts, r.motions, (int)r.has_min, r.min.clearance, r.min.pose,
         r.min.cell_x, r.min.cell_y, r.min.x, r.min.y, r.window);
  for (size_t i = 0; i < r.contacts; i++)
    printf("CONTACT %zu %zu %zu %.17g\n", contacts[i].pose, contacts[i].cell_x, contacts[i].cell_y,
           contacts[i].clearance);
  printf("MESSAGE %s\n", vouch_navfn_last_error());
  free(contacts);
  free(x);
  free(y);
  free(yaw);
  free(map);
  return 0;
}

static void report(const char *name, VouchNavfnStatus s) {
  printf("%s %d %s\n", name, (int)s, vouch_navfn_last_error());
}

static int errors(void) {
  unsigned char map[16] = {0};
  unsigned char out[16];
  map[5] = 254;
  double x[2] = {0.5, 3.5}, y[2] = {0.5, 0.5}, yaw[2] = {0.0, 0.0};
  double bad_x[2] = {0.5, NAN};
  VouchNavfnBodyReport r;
  VouchNavfnClearance one[1];
  report("inflate_null_costs", vouch_navfn_inflate(NULL, 16, 4, 4, 1.0, 0.3, NULL, NULL, out, 16));
  report("inflate_null_out", vouch_navfn_inflate(map, 16, 4, 4, 1.0, 0.3, NULL, NULL, NULL, 16));
  report("inflate_short_costs", vouch_navfn_inflate(map, 3, 4, 4, 1.0, 0.3, NULL, NULL, out, 16));
  report("inflate_small_buffer", vouch_navfn_inflate(map, 16, 4, 4, 1.0, 0.3, NULL, NULL, out, 8));
  report("inflate_bad_footprint",
         vouch_navfn_inflate(map, 16, 4, 4, 1.0, 0.0, "[[1,1],[1,-1]", NULL, out, 16));
  report("inflate_two_points",
         vouch_navfn_inflate(map, 16, 4, 4, 1.0, 0.0, "[[1,1],[1,-1]]", NULL, out, 16));
  report("inflate_negative_radius",
         vouch_navfn_inflate(map, 16, 4, 4, 1.0, -1.0, NULL, NULL, out, 16));
  report("inflate_bad_resolution",
         vouch_navfn_inflate(map, 16, 4, 4, 0.0, 0.3, NULL, NULL, out, 16));
  VouchNavfnInflationParams p = vouch_navfn_default_inflation_params();
  p.cost_scaling_factor = -2.0;
  report("inflate_negative_k", vouch_navfn_inflate(map, 16, 4, 4, 1.0, 0.3, NULL, &p, out, 16));
  p = vouch_navfn_default_inflation_params();
  p.footprint_padding = -0.5;
  report("inflate_negative_padding",
         vouch_navfn_inflate(map, 16, 4, 4, 1.0, 0.3, NULL, &p, out, 16));
  report("inflate_ok", vouch_navfn_inflate(map, 16, 4, 4, 1.0, 0.3, NULL, NULL, out, 16));
  report("body_null_costs",
         vouch_navfn_check_body(NULL, 16, 4, 4, 0, 0, 1, 0.3, NULL, x, y, yaw, 2, 2.0, &r, NULL, 0));
  report("body_null_report",
         vouch_navfn_check_body(map, 16, 4, 4, 0, 0, 1, 0.3, NULL, x, y, yaw, 2, 2.0, NULL, NULL, 0));
  report("body_null_yaw",
         vouch_navfn_check_body(map, 16, 4, 4, 0, 0, 1, 0.3, NULL, x, y, NULL, 2, 2.0, &r, NULL, 0));
  report("body_long_costs",
         vouch_navfn_check_body(map, 16, 3, 4, 0, 0, 1, 0.3, NULL, x, y, yaw, 2, 2.0, &r, NULL, 0));
  report("body_empty_map",
         vouch_navfn_check_body(map, 0, 0, 4, 0, 0, 1, 0.3, NULL, x, y, yaw, 2, 2.0, &r, NULL, 0));
  report("body_bad_footprint", vouch_navfn_check_body(map, 16, 4, 4, 0, 0, 1, 0.0, "[[0,0],[1,x]]",
                                                      x, y, yaw, 2, 2.0, &r, NULL, 0));
  report("body_negative_radius",
         vouch_navfn_check_body(map, 16, 4, 4, 0, 0, 1, -0.3, NULL, x, y, yaw, 2, 2.0, &r, NULL, 0));
  report("body_nan_pose", vouch_navfn_check_body(map, 16, 4, 4, 0, 0, 1, 0.3, NULL, bad_x, y, yaw,
                                                 2, 2.0, &r, NULL, 0));
  report("body_negative_window",
         vouch_navfn_check_body(map, 16, 4, 4, 0, 0, 1, 0.3, NULL, x, y, yaw, 2, -1.0, &r, NULL, 0));
  report("body_bad_resolution",
         vouch_navfn_check_body(map, 16, 4, 4, 0, 0, 0, 0.3, NULL, x, y, yaw, 2, 2.0, &r, NULL, 0));
  report("body_no_poses", vouch_navfn_check_body(map, 16, 4, 4, 0, 0, 1, 0.3, NULL, NULL, NULL,
                                                 NULL, 0, 2.0, &r, NULL, 0));
  printf("body_no_poses_report ok=%d motions=%zu\n", (int)r.ok, r.motions);
  /* poses (0.5, 0.5) → (3.5, 0.5) along row 0; the lethal cell (1, 1) is 0.5 m above: a disc of
     0.3 m passes 0.2 m below it, one of 0.6 m touches it */
  report("body_clear",
         vouch_navfn_check_body(map, 16, 4, 4, 0, 0, 1, 0.3, NULL, x, y, yaw, 2, 2.0, &r, NULL, 0));
  printf("body_clear_report ok=%d contacts=%zu clearance=%.17g\n", (int)r.ok, r.contacts,
         r.min.clearance);
  report("body_small_buffer",
         vouch_navfn_check_body(map, 16, 4, 4, 0, 0, 1, 0.6, NULL, x, y, yaw, 2, 2.0, &r, one, 0));
  printf("body_small_buffer_report ok=%d contacts=%zu\n", (int)r.ok, r.contacts);
  report("body_contact",
         vouch_navfn_check_body(map, 16, 4, 4, 0, 0, 1, 0.6, NULL, x, y, yaw, 2, 2.0, &r, one, 1));
  printf("body_contact_report ok=%d contacts=%zu cell=%zu,%zu\n", (int)r.ok, r.contacts,
         one[0].cell_x, one[0].cell_y);
  return 0;
}

int main(int argc, char **argv) {
  if (argc == 13 && strcmp(argv[1], "inflate") == 0) return inflate(argv);
  if (argc == 10 && strcmp(argv[1], "body") == 0) return body(argv);
  if (argc == 2 && strcmp(argv[1], "errors") == 0) return errors();
  fprintf(stderr, "usage: see the comment at the top of costmap_body.c\n");
  return 2;
}
