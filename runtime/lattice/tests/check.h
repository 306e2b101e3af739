/* check.h - a minimal assertion helper for the lattice runtime's tests. */
#ifndef CHECK_H
#define CHECK_H

#include <stdio.h>

extern unsigned long check_count;
extern unsigned long check_failures;

/* Records one check; prints the first failures with their location. */
#define CHECK(cond)                                                                        \
    do {                                                                                   \
        check_count++;                                                                     \
        if (!(cond)) {                                                                     \
            check_failures++;                                                              \
            if (check_failures <= 30u) {                                                   \
                fprintf(stderr, "%s:%d: CHECK failed: %s\n", __FILE__, __LINE__, #cond);   \
            }                                                                              \
        }                                                                                  \
    } while (0)

/* Like CHECK, printing both values (as long). */
#define CHECK_EQ(a, b)                                                                     \
    do {                                                                                   \
        long check_a_ = (long)(a);                                                         \
        long check_b_ = (long)(b);                                                         \
        check_count++;                                                                     \
        if (check_a_ != check_b_) {                                                        \
            check_failures++;                                                              \
            if (check_failures <= 30u) {                                                   \
                fprintf(stderr, "%s:%d: CHECK failed: %s == %s (%ld != %ld)\n", __FILE__,  \
                        __LINE__, #a, #b, check_a_, check_b_);                             \
            }                                                                              \
        }                                                                                  \
    } while (0)

/* The test groups (one file each). */
void test_laws(void);
void test_packets(void);
void test_sim(void);
void test_describe(void);
void test_dissemination(void);

#endif /* CHECK_H */
