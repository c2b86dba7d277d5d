/*
 * vouch translation-validation driver: the answers of a run. The real oracle of the header
 * (fp_cond, fp_code, fp_value) takes each answer from the request's prefix, then, when
 * exploring, answers 0 and stacks the other answers as pending prefixes (depth first, false
 * first); every answer and event is recorded. Included by explore_driver.c, whose
 * `struct driver` (D) and helpers it uses; not a separate translation unit.
 */
/* ---- answers ---- */
static void push_pending(size_t keep, long alt)
{
  size_t need = D->n_pending + keep + 2;
  if (need > D->cap_pending) {
    D->cap_pending = need * 2;
    D->pending = grow(D->pending, D->cap_pending * sizeof(long));
  }
  memcpy(D->pending + D->n_pending, D->taken, keep * sizeof(long));
  D->pending[D->n_pending + keep] = alt;
  D->pending[D->n_pending + keep + 1] = (long)(keep + 1);
  D->n_pending += keep + 2;
}

static int pop_pending(void)
{
  if (D->n_pending == 0) { return 0; }
  size_t n = (size_t)D->pending[D->n_pending - 1];
  D->n_pending -= n + 1;
  memcpy(D->prefix, D->pending + D->n_pending, n * sizeof(long));
  D->n_prefix = n;
  return 1;
}

static void reserve_answers(size_t n)
{
  if (n > D->cap_answers) {
    D->cap_answers = n * 2;
    D->prefix = grow(D->prefix, D->cap_answers * sizeof(long));
    D->taken = grow(D->taken, D->cap_answers * sizeof(long));
  }
}

static long next_number(int is_value)
{
  long n;
  if (D->mode == SCRIPT) {
    n = D->n_taken < D->n_prefix ? D->prefix[D->n_taken] : 0;
    D->n_taken++;
    return n;
  }
  if (D->n_taken >= (size_t)D->question_limit) { longjmp(D->too_long, 1); }
  if (D->n_taken < D->n_prefix) {
    n = D->prefix[D->n_taken];
  } else if (D->mode == EXPLORE) {
    n = 0;
    if (is_value) {
      for (long v = D->value_hi; v >= D->value_lo; v--) {
        if (v != 0) { push_pending(D->n_taken, 2 * v); }
      }
    } else {
      push_pending(D->n_taken, 1);
    }
  } else {
    D->deviated |= D->mode == FORCED;
    n = 0;
  }
  D->taken[D->n_taken++] = n;
  return n;
}

bool fp_cond(const char *text)
{
  bool v = (next_number(0) & 1) != 0;
  if (D->rec) { put_s(D->rec, v ? "C 1 " : "C 0 "); put_text(D->rec, text); }
  return v;
}

void fp_code(const char *text)
{
  if (D->rec) { put_s(D->rec, "X "); put_text(D->rec, text); }
}

int fp_value(const char *text)
{
  long v;
  /* same literal test and number-to-value map as the stub runtime's own oracle */
  if (!fp_literal_value(text, &v)) {
    v = fp_value_of_number(next_number(1));
  }
  if (D->rec) { put_s(D->rec, "V "); put_l(D->rec, v); put_s(D->rec, " "); put_text(D->rec, text); }
  return (int)v;
}
