/* test_main.c - runs the lattice runtime's tests; exits non-zero on any failure. */
#include "check.h"
#include "dr_conf.h"

int main(void)
{
    test_laws();
#if !DR_CONF_SYNC
    /* These craft packets and NV records byte by byte, in the layout without synchronous
     * groups (a DR_CONF_SYNC build carries the ready bits and the countdown too). */
    test_packets();
    test_sim();
    test_dissemination();
#endif
    test_describe();
    test_sync();
    printf("lattice tests (window %d, %s dissemination%s): %lu checks, %lu failed\n",
           DR_CONF_WINDOW,
           DR_CONF_LATTICE_DISSEMINATION == DR_DISSEMINATION_ADAPTIVE ? "adaptive" : "fixed",
           DR_CONF_SYNC ? ", synchronous groups" : "",
           dr_fake_checks,
           dr_fake_failures);
    return dr_fake_failures == 0u && dr_fake_misuses == 0u ? 0 : 1;
}
