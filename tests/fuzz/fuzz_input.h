/* Shared by the libFuzzer harnesses: the readers under test take a path, so
 * each input is written to a file in a private temporary directory (under
 * $TMPDIR), removed when the fuzzer exits normally. */
#ifndef TESTS_FUZZ_FUZZ_INPUT_H
#define TESTS_FUZZ_FUZZ_INPUT_H

#include <stddef.h>
#include <stdint.h>

/* The path of `name` in the private directory (created on the first call).
 * At most 8 names; the string lives until exit. */
const char *fuzz_input_path(const char *name);

/* Replaces the file at `path` with `size` bytes of `data`; aborts on failure
 * (the harness could not test anything). */
void fuzz_write_file(const char *path, const void *data, size_t size);

/* Reads every byte of a buffer, so that AddressSanitizer checks the reader
 * really allocated what its counts promise. */
uint8_t fuzz_touch(const void *data, size_t size);

#endif
