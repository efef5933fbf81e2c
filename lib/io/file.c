/* Whole-file reads, atomic writes, folders. */
#include <errno.h>
#include <fcntl.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include "core/context.h"
#include "io/file.h"

frig_status fr_open_regular(frig_ctx *ctx, const char *path, size_t max_size, int *fd_out, size_t *size) {
    *fd_out = -1;
    *size = 0;
    int fd = open(path, O_RDONLY | O_CLOEXEC);
    if (fd < 0) {
        if (errno == ENOENT) return fr_error(ctx, FRIG_ERR_NOT_FOUND, "%s: no such file", path);
        return fr_error(ctx, FRIG_ERR_IO, "%s: cannot open (%s)", path, strerror(errno));
    }
    struct stat st;
    if (fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
        close(fd);
        return fr_error(ctx, FRIG_ERR_IO, "%s: not a regular file", path);
    }
    if ((unsigned long long)st.st_size > max_size) {
        close(fd);
        return fr_error(ctx, FRIG_ERR_TOO_LARGE, "%s: file of %lld bytes is over the limit of %zu", path,
                        (long long)st.st_size, max_size);
    }
    *fd_out = fd;
    *size = (size_t)st.st_size;
    return FRIG_OK;
}

/* A large fresh buffer's pages faulted in by one call before the read fills them: each page's
 * first touch is otherwise a trap of its own, costly in a virtual machine (a 53 MB model file:
 * 13,000 of them). Best effort: where the kernel lacks MADV_POPULATE_WRITE (before Linux 5.14) the
 * read faults the pages in as before. */
#define PREFAULT_MIN ((size_t)1 << 20)
static void prefault(void *p, size_t n) {
#ifdef MADV_POPULATE_WRITE
    long page = sysconf(_SC_PAGESIZE);
    if (n < PREFAULT_MIN || page <= 0) return;
    uintptr_t mask = (uintptr_t)page - 1, a = ((uintptr_t)p + mask) & ~mask, e = ((uintptr_t)p + n) & ~mask;
    if (e > a) (void)madvise((void *)a, e - a, MADV_POPULATE_WRITE);
#else
    (void)p, (void)n;
#endif
}

frig_status fr_read_file(frig_ctx *ctx, const char *path, size_t max_size, unsigned char **data, size_t *size) {
    *data = NULL;
    *size = 0;
    int fd;
    size_t n;
    frig_status s = fr_open_regular(ctx, path, max_size, &fd, &n);
    if (s) return s;
    FILE *fp = fdopen(fd, "rb");
    if (!fp) {
        close(fd);
        return fr_error(ctx, FRIG_ERR_IO, "%s: cannot open (%s)", path, strerror(errno));
    }
    unsigned char *buf = malloc(n ? n : 1);
    if (!buf) {
        fclose(fp);
        return fr_nomem(ctx, path);
    }
    prefault(buf, n);
    size_t got = fread(buf, 1, n, fp);
    int err = ferror(fp);
    fclose(fp);
    if (got != n || err) {
        free(buf);
        return fr_error(ctx, FRIG_ERR_IO, "%s: read error after %zu of %zu bytes", path, got, n);
    }
    *data = buf;
    *size = n;
    return FRIG_OK;
}

frig_status fr_atomic_open(frig_ctx *ctx, const char *path, fr_atomic_file *af) {
    memset(af, 0, sizeof *af);
    size_t len = strlen(path);
    af->final_path = strdup(path);
    af->temp_path = malloc(len + 16);
    if (!af->final_path || !af->temp_path) {
        fr_atomic_abort(af);
        return fr_nomem(ctx, "a file name");
    }
    /* Hidden temporary beside the target, so rename() stays on one file system. */
    const char *base = fr_path_base(path);
    size_t dirlen = (size_t)(base - path);
    memcpy(af->temp_path, path, dirlen);
    snprintf(af->temp_path + dirlen, len - dirlen + 16, ".%s.XXXXXX", base);
    int fd = mkstemp(af->temp_path);
    if (fd < 0) {
        frig_status s = fr_error(ctx, FRIG_ERR_IO, "%s: cannot create a file there (%s)", path, strerror(errno));
        free(af->temp_path);
        af->temp_path = NULL;
        fr_atomic_abort(af);
        return s;
    }
    fchmod(fd, 0644);
    af->fp = fdopen(fd, "wb");
    if (!af->fp) {
        close(fd);
        fr_atomic_abort(af);
        return fr_error(ctx, FRIG_ERR_IO, "%s: cannot open a stream", path);
    }
    return FRIG_OK;
}

void fr_atomic_abort(fr_atomic_file *af) {
    if (af->fp) fclose(af->fp);
    if (af->temp_path) unlink(af->temp_path);
    free(af->temp_path);
    free(af->final_path);
    memset(af, 0, sizeof *af);
}

frig_status fr_atomic_commit(frig_ctx *ctx, fr_atomic_file *af) {
    frig_status s = FRIG_OK;
    int bad = ferror(af->fp) || fflush(af->fp) != 0 || fsync(fileno(af->fp)) != 0;
    int saved = errno;
    if (fclose(af->fp) != 0) bad = 1;
    af->fp = NULL;
    if (bad) {
        s = fr_error(ctx, FRIG_ERR_IO, "%s: write failed (%s); the old file, if any, is untouched",
                     af->final_path, strerror(saved));
    } else if (rename(af->temp_path, af->final_path) != 0) {
        s = fr_error(ctx, FRIG_ERR_IO, "%s: cannot rename into place (%s)", af->final_path, strerror(errno));
    } else {
        free(af->temp_path);
        af->temp_path = NULL; /* renamed: nothing to unlink */
    }
    fr_atomic_abort(af);
    return s;
}

frig_status fr_write_file_atomic(frig_ctx *ctx, const char *path, const void *data, size_t size) {
    fr_atomic_file af;
    frig_status s = fr_atomic_open(ctx, path, &af);
    if (s) return s;
    if (size && fwrite(data, 1, size, af.fp) != size) {
        fr_atomic_abort(&af);
        return fr_error(ctx, FRIG_ERR_IO, "%s: write failed (%s)", path, strerror(errno));
    }
    return fr_atomic_commit(ctx, &af);
}

frig_status fr_make_dirs(frig_ctx *ctx, const char *path) {
    char *p = strdup(path);
    if (!p) return fr_nomem(ctx, "a path");
    for (char *c = p + 1;; c++) {
        if (*c == '/' || *c == 0) {
            char keep = *c;
            *c = 0;
            if (mkdir(p, 0755) != 0 && errno != EEXIST) {
                frig_status s = fr_error(ctx, FRIG_ERR_IO, "%s: cannot create folder (%s)", p, strerror(errno));
                free(p);
                return s;
            }
            *c = keep;
            if (!keep) break;
        }
    }
    struct stat st;
    int ok = stat(path, &st) == 0 && S_ISDIR(st.st_mode);
    free(p);
    return ok ? FRIG_OK : fr_error(ctx, FRIG_ERR_IO, "%s: exists and is not a folder", path);
}

char *fr_path_join(const char *dir, const char *name) {
    size_t a = strlen(dir), b = strlen(name);
    char *s = malloc(a + b + 2);
    if (!s) return NULL;
    memcpy(s, dir, a);
    size_t k = a;
    if (a && dir[a - 1] != '/') s[k++] = '/';
    memcpy(s + k, name, b + 1);
    return s;
}

const char *fr_path_base(const char *path) {
    const char *slash = strrchr(path, '/');
    return slash ? slash + 1 : path;
}
