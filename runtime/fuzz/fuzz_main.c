/* fuzz_main.c - the plain driver (when not linked with libFuzzer): runs every file named on
 * the command line through LLVMFuzzerTestOneInput, then a number of deterministic mutations
 * of them (xorshift32): bit flips, byte sets, insertions, deletions, repeats and splices.
 *   fuzz_<protocol> [-n RUNS] [-s SEED] [-w LAST] FILE...
 * With -w, an input that breaks a law or trips a sanitizer is written to LAST.
 * Exit 0 when nothing broke (a broken law aborts), 2 on bad usage or an unreadable file. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "fuzz.h"
#ifdef __SANITIZE_ADDRESS__
#include <sanitizer/common_interface_defs.h>
#endif

#define MAX_FILES 128u
#define MAX_MUTATIONS 4u

static uint8_t corpus[MAX_FILES][FUZZ_MAX_INPUT];
static size_t corpus_len[MAX_FILES];
static unsigned n_files;
static uint8_t input[FUZZ_MAX_INPUT];
static uint32_t rng_state;
static const char *last_path;

static const uint8_t *current;
static size_t current_len;

/* Saves the running input to `last_path`: called when a law breaks or a sanitizer reports. */
static void save_current(void)
{
    FILE *f;
    if (last_path == NULL || current == NULL || (f = fopen(last_path, "wb")) == NULL) {
        return;
    }
    if (fwrite(current, 1, current_len, f) == current_len) {
        fprintf(stderr, "fuzz: the failing input is in %s\n", last_path);
    }
    fclose(f);
}

static void run(const uint8_t *data, size_t len)
{
    current = data;
    current_len = len;
    LLVMFuzzerTestOneInput(data, len);
}

static uint32_t next(void)
{
    uint32_t x = rng_state;
    x ^= x << 13;
    x ^= x >> 17;
    x ^= x << 5;
    rng_state = x;
    return x;
}

/* A number below `n` (n > 0). */
static uint32_t below(uint32_t n)
{
    return next() % n;
}

static int load(const char *path)
{
    FILE *f;
    size_t n;
    if (n_files >= MAX_FILES) {
        fprintf(stderr, "fuzz: more than %u corpus files\n", MAX_FILES);
        return 0;
    }
    f = fopen(path, "rb");
    if (f == NULL) {
        fprintf(stderr, "fuzz: %s: cannot open\n", path);
        return 0;
    }
    n = fread(corpus[n_files], 1, FUZZ_MAX_INPUT, f);
    if (ferror(f) || fgetc(f) != EOF) {
        fprintf(stderr, "fuzz: %s: unreadable or above %u bytes\n", path, FUZZ_MAX_INPUT);
        fclose(f);
        return 0;
    }
    fclose(f);
    corpus_len[n_files++] = n;
    return 1;
}

/* Opens a gap of up to `gap` bytes at `at` (less when the input is full); returns its size. */
static size_t open_gap(size_t len, size_t at, size_t gap)
{
    if (gap > FUZZ_MAX_INPUT - len) {
        gap = FUZZ_MAX_INPUT - len;
    }
    memmove(input + at + gap, input + at, len - at);
    return gap;
}

/* Copies up to `n` bytes of a corpus file into the input at a random place. */
static size_t splice(size_t len, size_t n)
{
    uint32_t f = below(n_files);
    size_t from;
    size_t at;
    if (corpus_len[f] == 0u) {
        return len;
    }
    from = below((uint32_t)corpus_len[f]);
    if (n > corpus_len[f] - from) {
        n = corpus_len[f] - from;
    }
    at = below((uint32_t)len + 1u);
    n = open_gap(len, at, n);
    memcpy(input + at, corpus[f] + from, n);
    return len + n;
}

/* One mutation of input[0..len); returns the new length. */
static size_t mutate(size_t len)
{
    static const uint8_t special[6] = { 0x00u, 0xFFu, 0x7Fu, 0x80u, 0x01u, 0xFEu };
    size_t at = len ? below((uint32_t)len) : 0u;
    size_t n = 1u + below(16u);
    size_t i;
    switch (below(6u)) {
    case 0: /* flip a bit */
        if (len) input[at] ^= (uint8_t)(1u << below(8u));
        return len;
    case 1: /* set a byte, often to an edge value */
        if (len) input[at] = below(2u) ? special[below(6u)] : (uint8_t)next();
        return len;
    case 2: /* insert random bytes */
        n = open_gap(len, at, n);
        for (i = 0; i < n; i++) input[at + i] = (uint8_t)next();
        return len + n;
    case 3: /* delete a run */
        if (n > len - at) n = len - at;
        memmove(input + at, input + at + n, len - at - n);
        return len - n;
    case 4: /* repeat a run */
        if (n > len - at) n = len - at;
        i = open_gap(len, at + n, n);
        memcpy(input + at + n, input + at, i);
        return len + i;
    default:
        return splice(len, n);
    }
}

static int usage(void)
{
    fprintf(stderr, "usage: fuzz [-n RUNS] [-s SEED] [-w LAST] FILE...\n");
    return 2;
}

/* Reads a number option; 0 on a malformed one. */
static int number(const char *text, unsigned long *out)
{
    char *end;
    *out = strtoul(text, &end, 10);
    return *text != '\0' && *end == '\0';
}

int main(int argc, char **argv)
{
    unsigned long runs = 10000ul;
    unsigned long seed = 1ul;
    unsigned long r;
    int i;
    for (i = 1; i < argc; i++) {
        if ((strcmp(argv[i], "-n") == 0 || strcmp(argv[i], "-s") == 0) && i + 1 < argc) {
            if (!number(argv[i + 1], argv[i][1] == 'n' ? &runs : &seed)) return usage();
            i++;
        } else if (strcmp(argv[i], "-w") == 0 && i + 1 < argc) {
            last_path = argv[++i];
        } else if (!load(argv[i])) {
            return 2;
        }
    }
    if (n_files == 0u) return usage();
    fuzz_failure_hook = save_current;
#ifdef __SANITIZE_ADDRESS__
    __sanitizer_set_death_callback(save_current);
#endif
    for (r = 0; r < n_files; r++) {
        run(corpus[r], corpus_len[r]);
    }
    rng_state = (uint32_t)(seed * 2654435761ul) | 1u;
    for (r = 0; r < runs; r++) {
        uint32_t f = below(n_files);
        size_t len = corpus_len[f];
        uint32_t m = 1u + below(MAX_MUTATIONS);
        memcpy(input, corpus[f], len);
        while (m--) len = mutate(len);
        run(input, len);
    }
    printf("fuzz: %u corpus files and %lu mutations (seed %lu): %lu frames delivered, %lu past "
           "the framing to the decoder; no law broken\n",
           n_files, runs, seed, fuzz_frames_delivered, fuzz_frames_decoded);
    if (runs > 0u && fuzz_frames_decoded == 0u) {
        /* A run whose frames all stop at the framing tests nothing behind it. */
        fprintf(stderr, "fuzz: no frame reached the decoder: regenerate the corpus (make corpus)\n");
        return 1;
    }
    return 0;
}
