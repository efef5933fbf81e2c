#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "testing.h"

int test_failures = 0;

/* The scratch folders test_temp_dir made: removed when every check passed (the suite's two builds
 * would otherwise keep gigabytes of workspaces and models), kept for a look when one failed or
 * when FRIG_KEEP_TEST_TMP is set. */
enum { TEMP_DIRS_MAX = 32 };
static char temp_dirs[TEMP_DIRS_MAX][4096];
static int temp_dir_count = 0;

static void remove_temp_dirs(void) {
    const char *keep = getenv("FRIG_KEEP_TEST_TMP");
    if (keep && *keep && strcmp(keep, "0") != 0) return;
    for (int i = 0; i < temp_dir_count; i++) {
        char cmd[4200];
        snprintf(cmd, sizeof cmd, "rm -rf '%.4095s'", temp_dirs[i]);
        if (system(cmd) != 0) fprintf(stderr, "cannot remove %s\n", temp_dirs[i]);
    }
    temp_dir_count = 0;
}

int test_result(const char *name) {
    if (test_failures) {
        fprintf(stderr, "%s: %d check(s) failed (scratch files kept under %s/test-tmp)\n", name, test_failures,
                FRIG_BINARY_DIR);
        return 1;
    }
    remove_temp_dirs();
    printf("%s: all checks passed\n", name);
    return 0;
}

int test_skip(const char *why) {
    if (getenv("FRIG_REQUIRE_DATA") && strcmp(getenv("FRIG_REQUIRE_DATA"), "0") != 0) {
        fprintf(stderr, "FAIL (FRIG_REQUIRE_DATA is set, so this may not be skipped): %s\n", why);
        return 1;
    }
    fprintf(stderr, "\n*** SKIPPED: %s ***\n\n", why);
    return 77;
}

const char *test_shared_dir(void) {
    const char *env = getenv("FRIG_SHARED");
    return env && *env ? env : FRIG_SOURCE_DIR "/../shared";
}

const char *test_shared_path(const char *rel) {
    static char buf[4096];
    snprintf(buf, sizeof buf, "%s/%s", test_shared_dir(), rel);
    return buf;
}

int test_file_exists(const char *path) {
    struct stat st;
    return stat(path, &st) == 0;
}

const char *test_temp_dir(const char *name) {
    static char buf[4096];
    snprintf(buf, sizeof buf, "%s/test-tmp/%s", FRIG_BINARY_DIR, name);
    char cmd[8400];
    snprintf(cmd, sizeof cmd, "rm -rf '%s' && mkdir -p '%s'", buf, buf);
    if (system(cmd) != 0) fprintf(stderr, "cannot make %s\n", buf);
    int known = 0;
    for (int i = 0; i < temp_dir_count; i++) known |= strcmp(temp_dirs[i], buf) == 0;
    if (!known && temp_dir_count < TEMP_DIRS_MAX) snprintf(temp_dirs[temp_dir_count++], sizeof temp_dirs[0], "%s", buf);
    return buf;
}

unsigned char *test_read_file(const char *path, size_t *size) {
    *size = 0;
    FILE *fp = fopen(path, "rb");
    if (!fp) return NULL;
    fseek(fp, 0, SEEK_END);
    long n = ftell(fp);
    fseek(fp, 0, SEEK_SET);
    unsigned char *b = n >= 0 ? malloc((size_t)n + 1) : NULL;
    if (b) {
        *size = fread(b, 1, (size_t)n, fp);
        b[*size] = 0;
    }
    fclose(fp);
    return b;
}
