/*
 * vouch translation-validation driver: joining the runs of one call at stage starts (the K
 * request; see the protocol in explore_driver.c). Included by explore_driver.c, whose
 * `struct driver` (D) and helpers it uses; not a separate translation unit.
 *
 * Every `Stage(n)` label of the header's auto_nav calls vouch_at_stage(). There nothing of the
 * call is pending, so the registered bytes are the whole state of the call. An explored run
 * that, after its own new answers, reaches a stage start in a state an earlier run of the same
 * call had at a stage start stops there ("joined"); the runs from the copies that shift live
 * counters stop where they meet the explored run.
 */
/* The counters of the loops the current stage is not inside, back to their values at the
 * start of the call: the semantics never reads them there (a loop is entered at its
 * initialisation, which writes both), so states differing only in them are one state. */
static void canonicalise(void)
{
  for (size_t k = 0; D->mask && k < D->n_loops; k++) {
    long *l = D->loops + 4 * k;
    int inside = nav_block == l[1] && nav_stage > l[2] && nav_stage <= l[3];
    struct vouch_var *v = l[0] >= 0 && (size_t)l[0] < D->n_vars ? D->vars[l[0]] : NULL;
    if (!inside && v != NULL) { memcpy(v->addr, D->start + D->offset[l[0]], v->size); }
  }
}

static size_t state_hash(const unsigned char *s)
{
  size_t h = 2166136261u;
  for (size_t i = 0; i < D->state_len; i++) { h = (h ^ s[i]) * 16777619u; }
  return h;
}

/* The node holding the current state, or a new one (-1); -2 when there is no memory left
 * for another (the emulated board's RAM is small): the request is then cut. */
static long node_of_state(void)
{
  size_t width = D->state_len ? D->state_len : 1;
  if (D->join_bytes && (2 * (D->n_nodes + 1)) * (width + 2 * sizeof(long)) > D->join_bytes) {
    return -2;
  }
  if (2 * (D->n_nodes + 1) > D->n_slots) {
    size_t n = D->n_slots ? 2 * D->n_slots : 1024;
    long *slots = realloc(D->slots, n * sizeof(long));
    if (slots == NULL) { return -2; }
    D->slots = slots;
    memset(D->slots, 0, n * sizeof(long));
    D->n_slots = n;
    for (size_t i = 0; i < D->n_nodes; i++) {
      size_t h = state_hash(D->nodes + i * D->state_len) & (n - 1);
      while (D->slots[h]) { h = (h + 1) & (n - 1); }
      D->slots[h] = (long)i + 1;
    }
  }
  if (D->n_nodes + 1 > D->cap_nodes) {
    size_t cap = 2 * (D->n_nodes + 1);
    unsigned char *nodes = realloc(D->nodes, cap * (D->state_len ? D->state_len : 1));
    if (nodes == NULL) { return -2; }
    D->nodes = nodes;
    D->cap_nodes = cap;
  }
  unsigned char *here = D->nodes + D->n_nodes * D->state_len;
  capture(here);
  size_t h = state_hash(here) & (D->n_slots - 1);
  while (D->slots[h]) {
    long id = D->slots[h] - 1;
    if (memcmp(D->nodes + (size_t)id * D->state_len, here, D->state_len) == 0) { return id; }
    h = (h + 1) & (D->n_slots - 1);
  }
  D->slots[h] = (long)D->n_nodes + 1;
  D->n_nodes++;
  return -1;
}

static void snapshot(void)
{
  if (D->n_snaps + 1 > D->cap_snaps) {
    D->cap_snaps = 2 * (D->n_snaps + 1);
    D->snaps = grow(D->snaps, D->cap_snaps * (D->state_len ? D->state_len : 1));
    D->snap_ev = grow(D->snap_ev, D->cap_snaps * sizeof(size_t));
    D->snap_taken = grow(D->snap_taken, D->cap_snaps * sizeof(size_t));
    D->snap_node = grow(D->snap_node, D->cap_snaps * sizeof(long));
  }
  D->snap_node[D->n_snaps] = -1;
  capture(D->snaps + D->n_snaps * D->state_len);
  D->snap_ev[D->n_snaps] = D->ev.len;
  D->snap_taken[D->n_snaps] = D->n_taken;
  D->n_snaps++;
}

/* The set of (copy, join point) where the copy's run met the explored run: a later run
 * through that point with the same answers before it meets there too. */
static unsigned long met_key(size_t copy, long node)
{
  return ((unsigned long)node << 12 ^ (unsigned long)copy) + 1;
}

static int met_find(unsigned long key, int insert)
{
  if (insert && 2 * (D->n_met + 1) > D->n_met_slots) {
    size_t n = D->n_met_slots ? 2 * D->n_met_slots : 1024;
    unsigned long *old = D->met;
    size_t n_old = D->n_met_slots;
    D->met = grow(NULL, n * sizeof *D->met);
    memset(D->met, 0, n * sizeof *D->met);
    D->n_met_slots = n;
    D->n_met = 0;
    for (size_t i = 0; i < n_old; i++) { if (old[i]) { met_find(old[i], 1); } }
    free(old);
  }
  if (D->n_met_slots == 0) { return 0; }
  size_t h = (size_t)(key * 0x9E3779B97F4A7C15ull) & (D->n_met_slots - 1);
  while (D->met[h]) {
    if (D->met[h] == key) { return 1; }
    h = (h + 1) & (D->n_met_slots - 1);
  }
  if (insert) { D->met[h] = key; D->n_met++; }
  return 0;
}

/* Whether a counter variable's loop is one the current stage is not inside (put back). */
static int put_back(size_t id)
{
  for (size_t k = 0; D->mask && k < D->n_loops; k++) {
    long *l = D->loops + 4 * k;
    if ((size_t)l[0] == id) {
      return !(nav_block == l[1] && nav_stage > l[2] && nav_stage <= l[3]);
    }
  }
  return 0;
}

/* A copy's run at its j-th stage start: the same answers and events so far as the explored
 * run at its j-th, and the same state but for counters both have put back (each to its own
 * start): from here it is that run. */
static int meets_explored_run(size_t j)
{
  if (j >= D->n_snaps || D->n_taken != D->snap_taken[j] || D->ev2.len != D->snap_ev[j]
      || memcmp(D->ev2.p, D->ev.p, D->ev2.len) != 0) {
    return 0;
  }
  const unsigned char *snap = D->snaps + j * D->state_len;
  for (size_t i = 0; i < D->n_vars; i++) {
    struct vouch_var *v = D->vars[i];
    if (v && memcmp(v->addr, snap + D->offset[i], v->size) != 0 && !put_back(i)) { return 0; }
  }
  return 1;
}

void vouch_at_stage(void)
{
  if (!D->join || (D->mode != EXPLORE && D->mode != FORCED)) { return; }
  canonicalise();
  if (D->mode == FORCED && D->stoppable && meets_explored_run(D->snap_seen++)) {
    longjmp(D->too_long, 3);
  }
  if (D->mode != EXPLORE) { return; }
  snapshot();
  long id = node_of_state();
  if (id == -2) { longjmp(D->too_long, 4); }
  /* replaying the prefix: an earlier run of this call registered the point */
  D->snap_node[D->n_snaps - 1] = id >= 0 ? id : (long)D->n_nodes - 1;
  if (D->n_taken < D->n_prefix) { return; }
  if (id >= 0) {
    D->joined = id;
    longjmp(D->too_long, 2);
  }
}

