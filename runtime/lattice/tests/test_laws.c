/* test_laws.c - the shared state is a join-semilattice: join is commutative, associative,
 * idempotent and monotone on normalised states; normalise is canonical. */
#include <string.h>
#include "check.h"
#include "dr_lattice.h"

#define WIN ((uint16_t)DR_CONF_WINDOW)

static uint32_t rng = 0x12345678u;

static uint32_t next(void)
{
    rng ^= rng << 13;
    rng ^= rng >> 17;
    rng ^= rng << 5;
    return rng;
}

static int same(const dr_shared_t *a, const dr_shared_t *b)
{
    return a->epoch == b->epoch && a->low == b->low &&
           memcmp(a->done, b->done, sizeof a->done) == 0;
}

static void set(uint8_t *bits, uint16_t i)
{
    bits[i / 8u] = (uint8_t)(bits[i / 8u] | (1u << (i % 8u)));
}

static uint8_t get(const uint8_t *bits, uint16_t i)
{
    return (uint8_t)(((unsigned)bits[i / 8u] >> (i % 8u)) & 1u);
}

/* A random normalised state for n statements: epochs 0-2 (rarely the top), a random low,
 * bits of random density. */
static void random_state(dr_shared_t *s, uint16_t n)
{
    uint16_t i;
    uint32_t density = next() % 5u; /* out of 4: 0 none .. 4 all */
    memset(s, 0, sizeof *s);
    s->epoch = (uint16_t)(next() % 3u);
    if (next() % 50u == 0u) {
        s->epoch = 0xFFFFu;
    }
    s->low = (dr_stmt_t)(next() % (n + 1u));
    for (i = 0; i < WIN && (uint16_t)(s->low + i) < n; i++) {
        if (next() % 4u < density) {
            set(s->done, i);
        }
    }
    dr_shared_normalise(s, n);
}

static dr_shared_t joined(const dr_shared_t *a, const dr_shared_t *b, uint16_t n)
{
    dr_shared_t r = *a;
    dr_shared_join(&r, b, n);
    return r;
}

/* Everything a knows (done in its epoch) is still known by r. */
static int covers(const dr_shared_t *r, const dr_shared_t *a, uint16_t n)
{
    uint16_t s;
    if (r->epoch != a->epoch) {
        return r->epoch > a->epoch;
    }
    if (r->low < a->low) {
        return 0;
    }
    for (s = 0; s < n; s++) {
        if (dr_shared_is_done(a, (dr_stmt_t)s) && !dr_shared_is_done(r, (dr_stmt_t)s)) {
            return 0;
        }
    }
    return 1;
}

static void laws(uint16_t n, unsigned iterations)
{
    unsigned k;
    dr_shared_t a, b, c, ab, ba, ab_c, bc, a_bc, t, bottom;
    memset(&bottom, 0, sizeof bottom);
    dr_shared_normalise(&bottom, n);
    for (k = 0; k < iterations; k++) {
        random_state(&a, n);
        random_state(&b, n);
        random_state(&c, n);
        /* Make equal epochs (where the interesting merging happens) common. */
        if (k % 2u == 0u && a.epoch != 0xFFFFu && b.epoch != 0xFFFFu) {
            b.epoch = a.epoch;
            c.epoch = a.epoch;
        }
        t = a;
        dr_shared_normalise(&t, n);
        CHECK(same(&t, &a));                       /* normalise is idempotent */
        t = joined(&a, &a, n);
        CHECK(same(&t, &a));                       /* idempotence */
        ab = joined(&a, &b, n);
        ba = joined(&b, &a, n);
        CHECK(same(&ab, &ba));                     /* commutativity */
        ab_c = joined(&ab, &c, n);
        bc = joined(&b, &c, n);
        a_bc = joined(&a, &bc, n);
        CHECK(same(&ab_c, &a_bc));                 /* associativity */
        CHECK(covers(&ab, &a, n));                 /* monotonicity: an upper bound */
        CHECK(covers(&ab, &b, n));
        t = joined(&ab, &a, n);
        CHECK(same(&t, &ab));                      /* a <= a v b */
        t = joined(&a, &bottom, n);
        CHECK(same(&t, &a));                       /* bottom is the identity */
        CHECK(a.low <= n);
        CHECK(a.low < n || a.epoch == 0xFFFFu);    /* a complete epoch is rolled over */
        CHECK(!dr_shared_is_done(&a, a.low) || a.low >= n); /* low is the first not done */
    }
}

static void normalise_cases(void)
{
    dr_shared_t s;
    /* Only a completed prefix is compacted: 1 and 2 done, 0 not: low stays. */
    memset(&s, 0, sizeof s);
    set(s.done, 1);
    set(s.done, 2);
    dr_shared_normalise(&s, 5);
    CHECK_EQ(s.low, 0);
    CHECK(dr_shared_is_done(&s, 1) && dr_shared_is_done(&s, 2) && !dr_shared_is_done(&s, 0));
    set(s.done, 0);
    dr_shared_normalise(&s, 5);
    CHECK_EQ(s.low, 3);
    CHECK_EQ(s.epoch, 0);
    CHECK(!dr_shared_is_done(&s, 3));
    CHECK(s.done[0] == 0u);
    set(s.done, 1);
    dr_shared_normalise(&s, 5);
    CHECK_EQ(s.low, 3);
    CHECK(get(s.done, 1) && dr_shared_is_done(&s, 4)); /* statement 4, re-based */
    /* Completing the epoch rolls it over. */
    set(s.done, 0);
    dr_shared_normalise(&s, 5);
    CHECK_EQ(s.epoch, 1);
    CHECK_EQ(s.low, 0);
    CHECK(s.done[0] == 0u);
    /* The top is never rolled over. */
    memset(&s, 0, sizeof s);
    s.epoch = 0xFFFFu;
    s.low = 5;
    dr_shared_normalise(&s, 5);
    CHECK_EQ(s.epoch, 0xFFFF);
    CHECK_EQ(s.low, 5);
    /* No statements: every state is the top. */
    memset(&s, 0, sizeof s);
    dr_shared_normalise(&s, 0);
    CHECK_EQ(s.epoch, 0xFFFF);
    CHECK_EQ(s.low, 0);
    /* Bits beyond the last statement are dropped; so is a low beyond it. */
    memset(&s, 0, sizeof s);
    s.done[0] = 0xF6u;
    dr_shared_normalise(&s, 3);
    CHECK_EQ(s.done[0], 0x06);
    memset(&s, 0, sizeof s);
    s.low = 9;
    dr_shared_normalise(&s, 3);
    CHECK_EQ(s.epoch, 1);
    CHECK_EQ(s.low, 0);
    /* A statement beyond the window is never done (and never written). */
    memset(&s, 0, sizeof s);
    memset(s.done, 0xFF, sizeof s.done);
    s.done[0] = 0xFEu;
    dr_shared_normalise(&s, 200);
    CHECK(!dr_shared_is_done(&s, WIN));
    CHECK(dr_shared_is_done(&s, (uint16_t)(WIN - 1u)));
    /* Joining re-bases on the higher low and keeps the union. */
    {
        dr_shared_t a, b;
        memset(&a, 0, sizeof a);
        memset(&b, 0, sizeof b);
        a.low = 2;
        set(a.done, 1);   /* statement 3 */
        set(b.done, 0);   /* statement 0 */
        set(b.done, 1);   /* statement 1 */
        set(b.done, 4);   /* statement 4 */
        dr_shared_join(&a, &b, 10);
        CHECK_EQ(a.low, 2);
        CHECK(!dr_shared_is_done(&a, 2));
        CHECK(dr_shared_is_done(&a, 3) && dr_shared_is_done(&a, 4) && !dr_shared_is_done(&a, 5));
        /* A higher epoch wins wholesale. */
        memset(&b, 0, sizeof b);
        b.epoch = 1;
        dr_shared_join(&a, &b, 10);
        CHECK_EQ(a.epoch, 1);
        CHECK_EQ(a.low, 0);
        CHECK(!dr_shared_is_done(&a, 3));
    }
}

void test_laws(void)
{
    static const uint16_t sizes[] = { 1, 2, 3, 7, 8, 9, 13, 16, 17, 24, 40, 64 };
    unsigned i;
    normalise_cases();
    for (i = 0; i < sizeof sizes / sizeof sizes[0]; i++) {
        laws(sizes[i], 3000u);
    }
}
