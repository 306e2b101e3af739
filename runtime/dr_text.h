/* dr_text.h - a bounded text writer for debugging descriptions (no printf family, MCU-safe).
 *
 * Each function appends to `out` (capacity `cap` bytes, the final NUL included) at position
 * *n and advances *n; what does not fit is dropped. The caller writes the NUL at out[*n]. */
#ifndef DR_TEXT_H
#define DR_TEXT_H

#include <stdint.h>

/* Appends one character when there is room for it and the final NUL. Cost: O(1). */
void dr_text_char(char *out, uint8_t cap, uint8_t *n, char c);
/* Appends a NUL-terminated literal. Cost: O(length). */
void dr_text_str(char *out, uint8_t cap, uint8_t *n, const char *text);
/* Appends `v` in decimal. Cost: O(digits). */
void dr_text_decimal(char *out, uint8_t cap, uint8_t *n, uint32_t v);

#endif /* DR_TEXT_H */
