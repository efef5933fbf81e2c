/* A few helpers shared by the tests: checks that count failures, finding data, skipping. */
#ifndef FRIG_TESTING_H
#define FRIG_TESTING_H

#include <math.h>
#include <stdio.h>

extern int test_failures;

#define CHECK(cond)                                                                   \
    do {                                                                              \
        if (!(cond)) {                                                                \
            fprintf(stderr, "%s:%d: check failed: %s\n", __FILE__, __LINE__, #cond);  \
            test_failures++;                                                          \
        }                                                                             \
    } while (0)

#define CHECK_NEAR(a, b, tol)                                                                        \
    do {                                                                                             \
        double a_ = (a), b_ = (b);                                                                   \
        if (!(fabs(a_ - b_) <= (tol))) {                                                             \
            fprintf(stderr, "%s:%d: %s = %.9g, expected %.9g +- %g\n", __FILE__, __LINE__, #a, a_, b_, \
                    (double)(tol));                                                                  \
            test_failures++;                                                                         \
        }                                                                                            \
    } while (0)

/* 0 when no check failed (the test's temporary folders removed), else 1: return it from main. */
int test_result(const char *name);

/* Skip (exit code 77) with a loud message, or fail when FRIG_REQUIRE_DATA is set (CI). */
int test_skip(const char *why);

/* ../shared next to the source tree, or $FRIG_SHARED. */
const char *test_shared_dir(void);
/* Path inside the shared folder (static buffer, valid until the next call). */
const char *test_shared_path(const char *rel);
int test_file_exists(const char *path);
/* A whole file in a new buffer (NUL-terminated, caller frees); NULL if unreadable. */
unsigned char *test_read_file(const char *path, size_t *size);
/* A fresh empty temporary folder under the build tree (test-tmp/NAME), removed by test_result when
 * every check passed (kept on a failure, or with FRIG_KEEP_TEST_TMP=1). */
const char *test_temp_dir(const char *name);

/* The standard output of a reference implementation's command (dlib_ref, OpenCV through Python):
 * the command runs (its stream read while it runs), or, when $FRIG_REF_CACHE names a folder, the
 * answer that the same command line left there before is read instead. scripts/test.sh sets it,
 * empty at its start, so that the sanitized pass reads the plain pass's answers: the references
 * are other people's programs, unsanitized and the same in both passes. The command may redirect
 * its standard error itself. test_ref_close returns 0 when the command succeeded. */
FILE *test_ref_open(const char *cmd);
int test_ref_close(FILE *f);
/* The same, written to the file 'out'; 0 when the command succeeded. */
int test_ref_to_file(const char *cmd, const char *out);

#endif
