/* dr_text.c - a bounded text writer for debugging descriptions (see dr_text.h). */
#include "dr_text.h"

void dr_text_char(char *out, uint8_t cap, uint8_t *n, char c)
{
    if ((uint16_t)(*n + 1u) < (uint16_t)cap) {
        out[*n] = c;
        *n = (uint8_t)(*n + 1u);
    }
}

void dr_text_str(char *out, uint8_t cap, uint8_t *n, const char *text)
{
    for (; *text != '\0'; text++) {
        dr_text_char(out, cap, n, *text);
    }
}

void dr_text_decimal(char *out, uint8_t cap, uint8_t *n, uint32_t v)
{
    char digits[10];
    uint8_t k = 0;
    do {
        digits[k] = (char)('0' + (int)(v % 10u));
        k++;
        v /= 10u;
    } while (v != 0u);
    while (k > 0u) {
        k--;
        dr_text_char(out, cap, n, digits[k]);
    }
}
