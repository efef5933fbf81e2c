/* Per-photo point clouds (paper section 5.1's output, section 5.2's input): the frig_clouds
 * handle, the file name of each photo's cloud, and WORKSPACE/clouds/ (and clouds/margin/) on
 * disk. */
#include <dirent.h>
#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "core/context.h"
#include "frig/clouds.h"
#include "frig/rig.h"
#include "io/file.h"
#include "io/ply_reader.h"

typedef struct cloud {
    size_t count, margin; /* the arrays hold count points of the cloud, then margin of its margin */
    float *xyz, *normals, *confidence;
} cloud;

struct frig_clouds {
    size_t photos;
    cloud *c;
};

frig_status frig_clouds_create(frig_ctx *ctx, size_t photo_count, frig_clouds **out) {
    if (!out) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_clouds_create: NULL output");
    *out = NULL;
    frig_clouds *c = calloc(1, sizeof *c);
    if (c) c->c = calloc(photo_count + 1, sizeof *c->c);
    if (!c || !c->c) {
        free(c);
        return fr_nomem(ctx, "point clouds");
    }
    c->photos = photo_count;
    *out = c;
    return FRIG_OK;
}

static void cloud_clear(cloud *c) {
    free(c->xyz), free(c->normals), free(c->confidence);
    memset(c, 0, sizeof *c);
}

void frig_clouds_free(frig_clouds *clouds) {
    if (!clouds) return;
    for (size_t i = 0; i < clouds->photos; i++) cloud_clear(&clouds->c[i]);
    free(clouds->c);
    free(clouds);
}

size_t frig_clouds_photo_count(const frig_clouds *clouds) { return clouds ? clouds->photos : 0; }

static float *copy_floats(const float *src, size_t n) {
    float *d = malloc(sizeof(float) * (n ? n : 1));
    if (d && n) memcpy(d, src, sizeof(float) * n);
    return d;
}

frig_status frig_clouds_set(frig_ctx *ctx, frig_clouds *clouds, size_t photo, size_t count, const float *xyz,
                            const float *normals, const float *confidence) {
    if (!clouds || photo >= clouds->photos)
        return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_clouds_set: no cloud slot for photo %zu", photo);
    if (count && (!xyz || !normals || !confidence))
        return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_clouds_set: points, normals and confidence are needed");
    cloud fresh = {0};
    if (count) {
        fresh.count = count;
        fresh.xyz = copy_floats(xyz, 3 * count);
        fresh.normals = copy_floats(normals, 3 * count);
        fresh.confidence = copy_floats(confidence, count);
        if (!fresh.xyz || !fresh.normals || !fresh.confidence) {
            cloud_clear(&fresh);
            return fr_nomem(ctx, "a point cloud");
        }
    }
    cloud_clear(&clouds->c[photo]);
    clouds->c[photo] = fresh;
    return FRIG_OK;
}

static const cloud *slot(const frig_clouds *clouds, size_t photo) {
    return clouds && photo < clouds->photos && clouds->c[photo].count ? &clouds->c[photo] : NULL;
}

/* n floats: the first keep of a, then add (may point into a: the caller's borrowed arrays). */
static float *joined(const float *a, size_t keep, const float *add, size_t n) {
    float *d = malloc(sizeof(float) * (n ? n : 1));
    if (d) {
        memcpy(d, a, sizeof(float) * keep);
        if (n > keep) memcpy(d + keep, add, sizeof(float) * (n - keep));
    }
    return d;
}

frig_status frig_clouds_set_margin(frig_ctx *ctx, frig_clouds *clouds, size_t photo, size_t count, const float *xyz,
                                   const float *normals, const float *confidence) {
    if (!slot(clouds, photo))
        return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_clouds_set_margin: photo %zu has no cloud", photo);
    if (count && (!xyz || !normals || !confidence))
        return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT,
                        "frig_clouds_set_margin: points, normals and confidence are needed");
    cloud *c = &clouds->c[photo];
    size_t n = c->count + count;
    cloud fresh = {c->count, count, joined(c->xyz, 3 * c->count, xyz, 3 * n),
                   joined(c->normals, 3 * c->count, normals, 3 * n), joined(c->confidence, c->count, confidence, n)};
    if (!fresh.xyz || !fresh.normals || !fresh.confidence) {
        cloud_clear(&fresh);
        return fr_nomem(ctx, "a cloud's margin");
    }
    cloud_clear(c); /* only now: the new points may have been read from these arrays */
    *c = fresh;
    return FRIG_OK;
}

size_t frig_clouds_count(const frig_clouds *clouds, size_t photo) {
    const cloud *c = slot(clouds, photo);
    return c ? c->count : 0;
}
size_t frig_clouds_margin_count(const frig_clouds *clouds, size_t photo) {
    const cloud *c = slot(clouds, photo);
    return c ? c->margin : 0;
}
const float *frig_clouds_xyz(const frig_clouds *clouds, size_t photo) {
    const cloud *c = slot(clouds, photo);
    return c ? c->xyz : NULL;
}
const float *frig_clouds_normals(const frig_clouds *clouds, size_t photo) {
    const cloud *c = slot(clouds, photo);
    return c ? c->normals : NULL;
}
const float *frig_clouds_confidence(const frig_clouds *clouds, size_t photo) {
    const cloud *c = slot(clouds, photo);
    return c ? c->confidence : NULL;
}

/* Every photo's cloud file name, in photo order (the first photo with a name keeps it, later
 * ones get the first free _2, _3, ...). A NULL-terminated array of n strings; NULL when out of
 * memory. */
static char **file_names(const frig_photoset *set, size_t n) {
    char **names = calloc(n + 1, sizeof *names);
    if (!names) return NULL;
    for (size_t i = 0; i < n; i++) {
        const char *path = frig_photoset_path(set, i);
        const char *base = fr_path_base(path ? path : "photo"), *dot = strrchr(base, '.');
        size_t stem = dot && dot != base ? (size_t)(dot - base) : strlen(base);
        size_t cap = stem + 32;
        names[i] = malloc(cap);
        if (!names[i]) goto fail;
        for (unsigned k = 1;; k++) {
            if (k == 1) snprintf(names[i], cap, "%.*s.ply", (int)stem, base);
            else snprintf(names[i], cap, "%.*s_%u.ply", (int)stem, base, k);
            size_t j = 0;
            while (j < i && strcmp(names[j], names[i]) != 0) j++;
            if (j == i) break;
        }
    }
    return names;
fail:
    for (size_t i = 0; i < n; i++) free(names[i]);
    free(names);
    return NULL;
}

static void free_names(char **names, size_t n) {
    if (!names) return;
    for (size_t i = 0; i < n; i++) free(names[i]);
    free(names);
}

frig_status frig_clouds_file_name(frig_ctx *ctx, const frig_photoset *set, size_t photo, char *buf, size_t size) {
    size_t n = frig_photoset_count(set);
    if (!set || photo >= n || !buf)
        return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_clouds_file_name: no photo %zu in the set", photo);
    char **names = file_names(set, photo + 1); /* later photos never change earlier names */
    if (!names) return fr_nomem(ctx, "cloud file names");
    size_t len = strlen(names[photo]);
    frig_status s = FRIG_OK;
    if (len + 1 > size) s = fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_clouds_file_name: buffer too small");
    else memcpy(buf, names[photo], len + 1);
    free_names(names, photo + 1);
    return s;
}

static int has_ply_suffix(const char *name) {
    size_t n = strlen(name);
    return n > 4 && !strcmp(name + n - 4, ".ply") && name[0] != '.';
}

/* Remove DIR's .ply files that are not among the names of photos with a cloud (with a margin
 * when margins is set). */
static frig_status remove_stale(frig_ctx *ctx, const char *dir, char **names, const frig_clouds *clouds, size_t n,
                                int margins) {
    DIR *d = opendir(dir);
    if (!d) return fr_error(ctx, FRIG_ERR_IO, "%s: cannot list the folder (%s)", dir, strerror(errno));
    frig_status s = FRIG_OK;
    struct dirent *e;
    while (!s && (e = readdir(d)) != NULL) {
        if (!has_ply_suffix(e->d_name)) continue;
        size_t i = 0;
        while (i < n && !(slot(clouds, i) && (!margins || clouds->c[i].margin) && !strcmp(names[i], e->d_name))) i++;
        if (i < n) continue;
        char *path = fr_path_join(dir, e->d_name);
        if (!path) s = fr_nomem(ctx, "a file name");
        else if (unlink(path) != 0 && errno != ENOENT)
            s = fr_error(ctx, FRIG_ERR_IO, "%s: cannot remove an old cloud (%s)", path, strerror(errno));
        free(path);
    }
    closedir(d);
    return s;
}

frig_status frig_clouds_save(frig_ctx *ctx, const frig_clouds *clouds, const frig_photoset *set,
                             const char *workspace) {
    if (!clouds || !set || !workspace)
        return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_clouds_save: NULL clouds, photo set or workspace");
    size_t n = frig_photoset_count(set);
    if (clouds->photos != n)
        return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_clouds_save: %zu cloud slots for %zu photos",
                        clouds->photos, n);
    char *dir = fr_path_join(workspace, "clouds");
    char *mdir = dir ? fr_path_join(dir, "margin") : NULL;
    char **names = file_names(set, n);
    frig_status s = !dir || !mdir || !names ? fr_nomem(ctx, "cloud file names") : fr_make_dirs(ctx, mdir);
    for (size_t i = 0; i < n && !s; i++) {
        const cloud *c = slot(clouds, i);
        if (!c) continue;
        char *path = fr_path_join(dir, names[i]);
        s = path ? frig_save_ply(ctx, path, c->count, c->xyz, c->normals, c->confidence) : fr_nomem(ctx, "a path");
        free(path);
        if (s || !c->margin) continue;
        path = fr_path_join(mdir, names[i]);
        s = path ? frig_save_ply(ctx, path, c->margin, c->xyz + 3 * c->count, c->normals + 3 * c->count,
                                 c->confidence + c->count)
                 : fr_nomem(ctx, "a path");
        free(path);
    }
    if (!s) s = remove_stale(ctx, dir, names, clouds, n, 0);
    if (!s) s = remove_stale(ctx, mdir, names, clouds, n, 1);
    free_names(names, n);
    free(mdir);
    free(dir);
    return s;
}

frig_status frig_clouds_load_ply(frig_ctx *ctx, frig_clouds *clouds, size_t photo, const char *path) {
    if (!clouds || photo >= clouds->photos || !path)
        return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_clouds_load_ply: no cloud slot for photo %zu", photo);
    fr_ply_cloud p;
    frig_status s = fr_ply_read(ctx, path, &p);
    if (s) return s;
    cloud_clear(&clouds->c[photo]);
    if (p.count) {
        clouds->c[photo] = (cloud){p.count, 0, p.xyz, p.normals, p.confidence};
    } else {
        fr_ply_cloud_free(&p);
    }
    return FRIG_OK;
}

/* The margin of photo's cloud from DIR/margin/NAME, when that file exists. */
static frig_status load_margin(frig_ctx *ctx, frig_clouds *clouds, size_t photo, const char *dir, const char *name) {
    char *mdir = fr_path_join(dir, "margin"), *path = mdir ? fr_path_join(mdir, name) : NULL;
    frig_status s = path ? FRIG_OK : fr_nomem(ctx, "a path");
    if (!s && access(path, F_OK) == 0) {
        fr_ply_cloud p;
        s = fr_ply_read(ctx, path, &p);
        if (!s) {
            s = frig_clouds_set_margin(ctx, clouds, photo, p.count, p.xyz, p.normals, p.confidence);
            fr_ply_cloud_free(&p);
        }
    }
    free(path), free(mdir);
    return s;
}

frig_status frig_clouds_load(frig_ctx *ctx, const frig_photoset *set, const char *workspace, frig_clouds **out) {
    if (!out) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_clouds_load: NULL output");
    *out = NULL;
    if (!set || !workspace)
        return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_clouds_load: NULL photo set or workspace");
    size_t n = frig_photoset_count(set);
    frig_clouds *c = NULL;
    frig_status s = frig_clouds_create(ctx, n, &c);
    char *dir = fr_path_join(workspace, "clouds");
    char **names = s ? NULL : file_names(set, n);
    if (!s && (!dir || !names)) s = fr_nomem(ctx, "cloud file names");
    for (size_t i = 0; i < n && !s; i++) {
        char *path = fr_path_join(dir, names[i]);
        if (!path) {
            s = fr_nomem(ctx, "a path");
            break;
        }
        if (access(path, F_OK) == 0) s = frig_clouds_load_ply(ctx, c, i, path);
        free(path);
        if (!s && slot(c, i)) s = load_margin(ctx, c, i, dir, names[i]);
    }
    free_names(names, n);
    free(dir);
    if (s) frig_clouds_free(c);
    else *out = c;
    return s;
}
