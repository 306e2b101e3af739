/* test_main.c - runs the lattice runtime's tests; exits non-zero on any failure. */
#include "check.h"
#include "dr_conf.h"

int main(void)
{
    test_laws();
    test_packets();
    test_sim();
    test_describe();
    test_dissemination();
    printf("lattice tests (window %d, %s dissemination): %lu checks, %lu failed\n",
           DR_CONF_WINDOW,
           DR_CONF_LATTICE_DISSEMINATION == DR_DISSEMINATION_ADAPTIVE ? "adaptive" : "fixed",
           dr_fake_checks,
           dr_fake_failures);
    return dr_fake_failures == 0u && dr_fake_misuses == 0u ? 0 : 1;
}
