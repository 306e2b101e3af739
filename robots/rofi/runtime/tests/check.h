/* check.h - the platform tests' assertions, in the style of runtime/testing/dr_fake.h (which
 * the tests cannot link: it is a platform of dr_hal.h itself). Each counts and reports, never
 * aborts, so one run shows every failure. */
#ifndef CHECK_H
#define CHECK_H

extern unsigned long checks;
extern unsigned long failures;
#define CHECK(cond) check((cond) != 0, #cond, __FILE__, __LINE__)
#define CHECK_EQ(a, b) check_eq((long)(a), (long)(b), #a, #b, __FILE__, __LINE__)
int check(int ok, const char *what, const char *file, int line);
int check_eq(long a, long b, const char *sa, const char *sb, const char *file, int line);

#endif /* CHECK_H */
