/* fuzz.h - what every fuzz target shares: the input as a file (the
 * parsers read paths, as the programs do), in a private directory made
 * once per process. A target defines LLVMFuzzerTestOneInput; libFuzzer
 * drives it (make fuzz), or replay.c runs it over files (make check). */
#ifndef TL_FUZZ_H
#define TL_FUZZ_H

#include <stddef.h>
#include <stdint.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* Writes data to <private dir>/name and returns the path (static
 * storage, overwritten by the next call); NULL on failure. */
const char *fuzz_file(const char *name, const uint8_t *data, size_t size);

#endif
