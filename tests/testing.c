#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "testing.h"

int test_failures = 0;

int test_result(const char *name) {
    if (test_failures) {
        fprintf(stderr, "%s: %d check(s) failed\n", name, test_failures);
        return 1;
    }
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
