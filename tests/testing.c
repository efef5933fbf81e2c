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

/* ---- reference answers, cached across the suite's two builds ------------------------------- */

enum { REF_OPEN_MAX = 8 };
static FILE *ref_cached[REF_OPEN_MAX]; /* streams read from the cache (fclose, not pclose) */

/* FNV-1a of the command line: the cache file's name. */
static unsigned long long ref_key(const char *cmd) {
    unsigned long long h = 1469598103934665603ull;
    for (const unsigned char *c = (const unsigned char *)cmd; *c; c++) h = (h ^ *c) * 1099511628211ull;
    return h;
}

FILE *test_ref_open(const char *cmd) {
    const char *dir = getenv("FRIG_REF_CACHE");
    if (!dir || !*dir) return popen(cmd, "r");
    char path[4200];
    snprintf(path, sizeof path, "%.4000s/%016llx.out", dir, ref_key(cmd));
    FILE *f = fopen(path, "r");
    if (f) {
        for (int i = 0; i < REF_OPEN_MAX; i++)
            if (!ref_cached[i]) {
                ref_cached[i] = f;
                return f;
            }
        fclose(f);
        return NULL;
    }
    /* Run it into a file of this process's own, keep that under the key when the command
     * succeeded, and stream it (the reader blocks only until the command is done). */
    size_t len = strlen(cmd) + 3 * strlen(path) + 256;
    char *sh = malloc(len);
    if (!sh) return NULL;
    snprintf(sh, len, "mkdir -p '%s' && ( %s ) > '%s.%ld' && mv '%s.%ld' '%s' && cat '%s' || { rm -f '%s.%ld'; exit 1; }",
             dir, cmd, path, (long)getpid(), path, (long)getpid(), path, path, path, (long)getpid());
    f = popen(sh, "r");
    free(sh);
    return f;
}

int test_ref_close(FILE *f) {
    if (!f) return -1;
    for (int i = 0; i < REF_OPEN_MAX; i++)
        if (ref_cached[i] == f) {
            ref_cached[i] = NULL;
            return fclose(f) == 0 ? 0 : -1;
        }
    return pclose(f);
}

int test_ref_to_file(const char *cmd, const char *out) {
    FILE *in = test_ref_open(cmd), *o = in ? fopen(out, "w") : NULL;
    int ok = in && o;
    char buf[1 << 14];
    size_t n;
    while (ok && (n = fread(buf, 1, sizeof buf, in)) > 0) ok = fwrite(buf, 1, n, o) == n;
    if (o && fclose(o) != 0) ok = 0;
    int rc = in ? test_ref_close(in) : -1;
    return ok && rc == 0 ? 0 : -1;
}
