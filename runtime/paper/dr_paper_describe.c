/* dr_paper_describe.c - a one-line description of a paper-protocol module's state, for
 * traces (host and simulator builds; not needed on the modules). */
#include "dr_paper.h"
#include "dr_text.h"

#define N_PENDING ((uint8_t)DR_CONF_MAX_PENDING)

/* Cost: O(N). */
uint8_t dr_module_describe(const dr_module_t *m, char *out, uint8_t cap)
{
    uint8_t n = 0;
    uint8_t i;
    uint8_t first = 1;
    if (cap == 0u) {
        return 0;
    }
    dr_text_char(out, cap, &n, 's');
    dr_text_decimal(out, cap, &n, m->global.state);
    dr_text_str(out, cap, &n, " a");
    dr_text_decimal(out, cap, &n, m->global.address);
    dr_text_str(out, cap, &n, " p{");
    for (i = 0; i < N_PENDING; i++) {
        if (m->global.pending[i] != 0u) {
            if (!first) {
                dr_text_char(out, cap, &n, ',');
            }
            first = 0;
            dr_text_decimal(out, cap, &n, m->global.pending[i]);
        }
    }
    dr_text_str(out, cap, &n, "} l");
    dr_text_decimal(out, cap, &n, m->local_state);
    out[n] = '\0';
    return n;
}
