/*
 * vouch translation-validation driver: the C state and the watch of static storage. The
 * registered variables (found in the `vouch_vars` linker section by their magic word) are the
 * state bytes: captured, restored, compared; every other byte of the program's static storage
 * is compared with its start-up image after every run (H lines). Included by
 * explore_driver.c, whose `struct driver` (D) it uses; not a separate translation unit.
 */
/* ---- the registered variables and the watched segment ---- */
static void collect_vars(void)
{
  size_t n = 0, max_id = 0;
  char *p = (char *)__start_vouch_vars, *q = (char *)__stop_vouch_vars;
  /* entries may be padded apart: find them by their magic word */
  for (char *c = p; c + sizeof(struct vouch_var) <= q; c += sizeof(long)) {
    struct vouch_var *v = (struct vouch_var *)c;
    if (v->magic == VOUCH_MAGIC) { n++; if ((size_t)v->id > max_id) { max_id = (size_t)v->id; } }
  }
  D->n_vars = n ? max_id + 1 : 0;
  D->vars = grow(NULL, D->n_vars * sizeof *D->vars);
  D->offset = grow(NULL, (D->n_vars + 1) * sizeof *D->offset);
  memset(D->vars, 0, D->n_vars * sizeof *D->vars);
  for (char *c = p; c + sizeof(struct vouch_var) <= q; c += sizeof(long)) {
    struct vouch_var *v = (struct vouch_var *)c;
    if (v->magic == VOUCH_MAGIC) { D->vars[v->id] = v; }
  }
  D->state_len = 0;
  for (size_t i = 0; i < D->n_vars; i++) {
    D->offset[i] = D->state_len;
    D->state_len += D->vars[i] ? D->vars[i]->size : 0;
  }
  D->offset[D->n_vars] = D->state_len;
  D->init_state = grow(NULL, D->state_len);
  D->state = grow(NULL, D->state_len);
  D->after = grow(NULL, D->state_len);
}

static void capture(unsigned char *s)
{
  for (size_t i = 0; i < D->n_vars; i++) {
    if (D->vars[i]) { memcpy(s + D->offset[i], D->vars[i]->addr, D->vars[i]->size); }
  }
}
/* Only variables whose bytes differ are written: a `const` plan variable lives in read-only
 * storage, and its bytes never differ. */
static void restore(const unsigned char *s)
{
  for (size_t i = 0; i < D->n_vars; i++) {
    struct vouch_var *v = D->vars[i];
    if (v && memcmp(v->addr, s + D->offset[i], v->size) != 0) {
      memcpy(v->addr, s + D->offset[i], v->size);
    }
  }
}

static int registered(const char *a)
{
  for (size_t i = 0; i < D->n_vars; i++) {
    const char *v = D->vars[i] ? (const char *)D->vars[i]->addr : NULL;
    if (v != NULL && a >= v && a < v + D->vars[i]->size) { return 1; }
  }
  return 0;
}

/* The program's static storage as the platform knows it; bytes outside every registered
 * variable are compared with their image after every run. */
static void watch_segment(void)
{
  char *lo, *hi;
  if (!vouch_watch_range(&lo, &hi) || hi <= lo) { return; }
  D->lo = lo;
  D->hi = hi;
  D->image = grow(NULL, (size_t)(D->hi - D->lo));
  D->clean = grow(NULL, sizeof *D->clean);
  D->n_clean = 0;
  /* runs of bytes outside every registered variable */
  for (char *c = D->lo; c < D->hi;) {
    while (c < D->hi && registered(c)) { c++; }
    char *s = c;
    while (c < D->hi && !registered(c)) { c++; }
    if (c > s) {
      D->clean = grow(D->clean, (D->n_clean + 1) * sizeof *D->clean);
      D->clean[D->n_clean][0] = (size_t)(s - D->lo);
      D->clean[D->n_clean][1] = (size_t)(c - D->lo);
      D->n_clean++;
    }
  }
  memcpy(D->image, D->lo, (size_t)(D->hi - D->lo));
  D->watching = 1;
}

/* Puts the watched bytes back as they were at start-up (after an in-process walk). */
static void reset_watched(void)
{
  for (size_t k = 0; D->watching && k < D->n_clean; k++) {
    size_t a = D->clean[k][0], b = D->clean[k][1];
    memcpy(D->lo + a, D->image + a, b - a);
  }
}

/* Notes bytes written outside the registered variables (D->hidden, printed with the record of
 * the run) and puts them back. */
static void hidden_check(void)
{
  if (!D->watching) { return; }
  for (size_t k = 0; k < D->n_clean; k++) {
    size_t a = D->clean[k][0], b = D->clean[k][1];
    if (memcmp(D->lo + a, D->image + a, b - a) == 0) { continue; }
    for (size_t i = a; i < b; i++) {
      if ((unsigned char)D->lo[i] != D->image[i]) {
        if (D->n_hidden < sizeof D->hidden / sizeof D->hidden[0]) { D->hidden[D->n_hidden++] = (long)i; }
        break;
      }
    }
    memcpy(D->lo + a, D->image + a, b - a);
  }
}

static void put_hidden(void)
{
  for (size_t i = 0; i < D->n_hidden; i++) {
    put_s(&D->out, "H ");
    put_l(&D->out, D->hidden[i]);
    put_s(&D->out, "\n");
  }
  D->n_hidden = 0;
}
