/* Files for frig run: content hashes for the stage records, folder listings, atomic writes of
 * the records and the report page, removing what an interrupted writer left behind, and the
 * clock and peak-memory readings the report shows. */
#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "run.h"

/* FNV-1a over 64-bit words (then the tail bytes) with a final avalanche: a change detector,
 * not a cryptographic hash. */
#define FNV_PRIME 0x100000001b3ull

void run_hash_init(run_hash *h) { h->h = 0xcbf29ce484222325ull; }

void run_hash_bytes(run_hash *h, const void *data, size_t n) {
    const unsigned char *p = data;
    uint64_t x = h->h;
    for (; n >= 8; n -= 8, p += 8) {
        uint64_t w = 0;
        for (int i = 0; i < 8; i++) w |= (uint64_t)p[i] << (8 * i);
        x = (x ^ w) * FNV_PRIME;
        x ^= x >> 29;
    }
    for (; n; n--, p++) x = (x ^ *p) * FNV_PRIME;
    h->h = x;
}

void run_hash_str(run_hash *h, const char *s) { run_hash_bytes(h, s, strlen(s) + 1); }

int run_hash_file(run_hash *h, const char *path) {
    int fd = open(path, O_RDONLY);
    if (fd < 0) return -1;
    static __thread unsigned char buf[1 << 16];
    ssize_t got;
    uint64_t total = 0;
    while ((got = read(fd, buf, sizeof buf)) > 0) run_hash_bytes(h, buf, (size_t)got), total += (uint64_t)got;
    int bad = got < 0;
    close(fd);
    run_hash_bytes(h, &total, sizeof total);
    return bad ? -1 : 0;
}

void run_hex(uint64_t v, char out[17]) {
    v ^= v >> 33, v *= 0xff51afd7ed558ccdull, v ^= v >> 33;
    snprintf(out, 17, "%016llx", (unsigned long long)v);
}

static int by_name(const void *a, const void *b) { return strcmp(*(char *const *)a, *(char *const *)b); }

int run_list_files(const char *dir, char ***out, size_t *count) {
    *out = NULL;
    *count = 0;
    DIR *d = opendir(dir);
    if (!d) return errno == ENOENT ? 0 : -1;
    char **names = NULL;
    size_t n = 0, cap = 0;
    int bad = 0;
    for (struct dirent *e; (e = readdir(d)) != NULL && !bad;) {
        if (e->d_name[0] == '.') continue;
        size_t len = strlen(dir) + strlen(e->d_name) + 2;
        char *full = malloc(len);
        if (!full) { bad = 1; break; }
        snprintf(full, len, "%s/%s", dir, e->d_name);
        struct stat st;
        if (stat(full, &st) != 0 || !S_ISREG(st.st_mode)) {
            free(full);
            continue;
        }
        if (n == cap) {
            cap = cap ? 2 * cap : 64;
            char **nn = realloc(names, cap * sizeof *names);
            if (!nn) {
                free(full);
                bad = 1;
                break;
            }
            names = nn;
        }
        names[n++] = full;
    }
    closedir(d);
    if (bad) {
        for (size_t i = 0; i < n; i++) free(names[i]);
        free(names);
        errno = ENOMEM;
        return -1;
    }
    if (n) qsort(names, n, sizeof *names, by_name);
    *out = names;
    *count = n;
    return 0;
}

int run_write_atomic(const char *path, const void *data, size_t size) {
    size_t len = strlen(path);
    char *tmp = malloc(len + 16);
    if (!tmp) return -1;
    const char *slash = strrchr(path, '/');
    size_t dirlen = slash ? (size_t)(slash - path) + 1 : 0;
    snprintf(tmp, len + 16, "%.*s.%s.XXXXXX", (int)dirlen, path, path + dirlen);
    int fd = mkstemp(tmp);
    if (fd < 0) {
        free(tmp);
        return -1;
    }
    fchmod(fd, 0644);
    size_t done = 0;
    while (done < size) {
        ssize_t w = write(fd, (const char *)data + done, size - done);
        if (w <= 0) break;
        done += (size_t)w;
    }
    int err = done < size || fsync(fd) != 0;
    int saved = errno;
    if (close(fd) != 0) err = 1;
    if (!err && rename(tmp, path) != 0) err = 1, saved = errno;
    if (err) unlink(tmp);
    free(tmp);
    errno = saved;
    return err ? -1 : 0;
}

char *run_read_text(const char *path, size_t *size) {
    FILE *fp = fopen(path, "rb");
    if (!fp) return NULL;
    char *buf = NULL;
    size_t n = 0, cap = 0, got;
    char chunk[65536];
    while ((got = fread(chunk, 1, sizeof chunk, fp)) > 0) {
        if (n + got + 1 > cap) {
            cap = 2 * (n + got + 1);
            char *b = realloc(buf, cap);
            if (!b) {
                free(buf);
                fclose(fp);
                return NULL;
            }
            buf = b;
        }
        memcpy(buf + n, chunk, got);
        n += got;
    }
    fclose(fp);
    if (!buf && !(buf = malloc(1))) return NULL;
    buf[n] = 0;
    if (size) *size = n;
    return buf;
}

/* ".NAME.XXXXXX": what mkstemp leaves of an atomic write that never got renamed. */
static int is_temp(const char *name) {
    size_t n = strlen(name);
    if (name[0] != '.' || n < 9 || name[n - 7] != '.') return 0;
    for (size_t i = n - 6; i < n; i++)
        if (!((name[i] >= 'a' && name[i] <= 'z') || (name[i] >= 'A' && name[i] <= 'Z') || (name[i] >= '0' && name[i] <= '9')))
            return 0;
    return 1;
}

void run_remove_temps(const char *dir) {
    DIR *d = opendir(dir);
    if (!d) return;
    for (struct dirent *e; (e = readdir(d)) != NULL;) {
        if (!is_temp(e->d_name)) continue;
        char path[8192];
        if (snprintf(path, sizeof path, "%s/%s", dir, e->d_name) < (int)sizeof path) unlink(path);
    }
    closedir(d);
}

int run_remove_tree(const char *path) {
    struct stat st;
    if (lstat(path, &st) != 0) return errno == ENOENT ? 0 : -1;
    if (!S_ISDIR(st.st_mode)) return unlink(path);
    DIR *d = opendir(path);
    if (!d) return -1;
    int bad = 0;
    for (struct dirent *e; (e = readdir(d)) != NULL;) {
        if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, "..")) continue;
        char sub[8192];
        if (snprintf(sub, sizeof sub, "%s/%s", path, e->d_name) >= (int)sizeof sub || run_remove_tree(sub)) bad = 1;
    }
    closedir(d);
    return bad || rmdir(path) ? -1 : 0;
}

double run_cpu_now(void) {
    struct rusage ru;
    if (getrusage(RUSAGE_SELF, &ru) != 0) return 0.0;
    return (double)ru.ru_utime.tv_sec + 1e-6 * (double)ru.ru_utime.tv_usec + (double)ru.ru_stime.tv_sec +
           1e-6 * (double)ru.ru_stime.tv_usec;
}

double run_now(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

void run_peak_reset(void) {
    int fd = open("/proc/self/clear_refs", O_WRONLY);
    if (fd < 0) return;
    if (write(fd, "5", 1) != 1) { /* an older kernel: the peak stays the process's */
    }
    close(fd);
}

double run_peak_mb(void) {
    FILE *fp = fopen("/proc/self/status", "r");
    if (!fp) return 0.0;
    char line[256];
    double kb = 0.0;
    while (fgets(line, sizeof line, fp))
        if (strncmp(line, "VmHWM:", 6) == 0) kb = strtod(line + 6, NULL);
    fclose(fp);
    return kb / 1024.0;
}
