/* dr_token_describe.c - a one-line description of a token-baseline module's state, for
 * traces (host and simulator builds; not needed on the modules). */
#include "dr_token.h"
#include "dr_text.h"

/* Cost: O(1). */
uint8_t dr_module_describe(const dr_module_t *m, char *out, uint8_t cap)
{
    uint8_t n = 0;
    if (cap == 0u) {
        return 0;
    }
    dr_text_str(out, cap, &n, "tok");
    if (m->holding == DR_NONE) {
        dr_text_char(out, cap, &n, '-');
    } else {
        dr_text_decimal(out, cap, &n, m->holding);
    }
    if (m->running) {
        dr_text_str(out, cap, &n, " run");
    }
    dr_text_str(out, cap, &n, " q");
    dr_text_decimal(out, cap, &n, m->n_queued);
    if (m->finished) {
        dr_text_str(out, cap, &n, " fin");
    }
    out[n] = '\0';
    return n;
}
