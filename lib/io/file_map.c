/* A whole file mapped read-only (file_map.h). */
#include <errno.h>
#include <string.h>
#include <sys/mman.h>
#include <unistd.h>

#include "core/context.h"
#include "io/file.h"
#include "io/file_map.h"

frig_status fr_file_map_open(frig_ctx *ctx, const char *path, size_t max_size, fr_file_map *map) {
    map->data = NULL;
    map->size = 0;
    int fd;
    size_t n;
    frig_status s = fr_open_regular(ctx, path, max_size, &fd, &n);
    if (s) return s;
    if (n == 0) {
        close(fd);
        return FRIG_OK;
    }
    void *p = mmap(NULL, n, PROT_READ, MAP_PRIVATE, fd, 0);
    int err = errno;
    close(fd);
    if (p == MAP_FAILED) return fr_error(ctx, FRIG_ERR_IO, "%s: cannot map (%s)", path, strerror(err));
    map->data = p;
    map->size = n;
    return FRIG_OK;
}

void fr_file_map_close(fr_file_map *map) {
    if (map->data) munmap((void *)map->data, map->size);
    map->data = NULL;
    map->size = 0;
}
