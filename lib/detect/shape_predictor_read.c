/* Reading dlib's shape_predictor (dlib/image_processing/shape_predictor.h, serialization
 * version 1) into flat arrays: the version int, the initial shape (a float column), the
 * forests (per cascade a vector of trees; a tree is its splits (idx1, idx2, thresh) and its
 * leaf vectors), then per cascade the feature pixels' anchor landmarks and their deltas.
 * Every count and index is checked, so a damaged file is refused, never trusted. */
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "detect/dlib_deserialize.h"
#include "detect/shape_predictor.h"
#include "io/file_map.h"

#define FR_SP_MAX_FILE ((size_t)1 << 31)

/* Growable arrays while the file is read (the final sizes are known only at the end). */
typedef struct sp_builder {
    fr_dlib_reader r;
    fr_shape_predictor *sp;
    size_t coords;                         /* 2 * parts */
    size_t trees, tree_cap;                /* split_begin has trees + 1 entries */
    size_t splits, split_cap;
    size_t leaves, leaf_cap;               /* in leaves of 'coords' floats */
    size_t features, feature_cap;
    size_t trees_expected;                 /* cascades x the first cascade's trees */
} sp_builder;

/* Make room for 'need' elements of 'elem' bytes in *p (capacity *cap, grown by half). */
static int reserve(void **p, size_t *cap, size_t need, size_t elem) {
    if (need <= *cap) return 1;
    size_t n = *cap + *cap / 2;
    if (n < need) n = need;
    if (n < 64) n = 64;
    if (n > SIZE_MAX / elem) return 0;
    void *q = realloc(*p, n * elem);
    if (!q) return 0;
    *p = q;
    *cap = n;
    return 1;
}

/* The first tree sizes the arrays for all: its count times the trees expected, but never more
 * than the bytes left in the file could hold (item_bytes each, at their smallest). One
 * allocation for a file like dlib's instead of a growing copy of 65 MB. */
static size_t first_need(const sp_builder *b, size_t cap, size_t need, size_t per_tree, size_t item_bytes) {
    if (cap || b->trees_expected < 2 || !per_tree) return need;
    size_t left = (b->r.size - b->r.pos) / item_bytes;
    size_t guess = per_tree > left / b->trees_expected ? left : per_tree * b->trees_expected;
    return guess > need ? guess : need;
}

static frig_status nomem(sp_builder *b) {
    b->r.status = fr_nomem(b->r.ctx, "a shape predictor's trees");
    return b->r.status;
}

/* Add "(cascade c, tree t)" to the message of a failure inside a tree. */
static frig_status at_tree(sp_builder *b, size_t cascade, size_t tree) {
    frig_ctx *ctx = b->r.ctx;
    if (ctx && ctx->status == b->r.status) {
        char msg[FR_ERRMSG_SIZE];
        memcpy(msg, ctx->errmsg, sizeof msg);
        msg[sizeof msg - 1] = 0;
        fr_error(ctx, b->r.status, "%s (cascade %zu, tree %zu)", msg, cascade, tree);
    }
    return b->r.status;
}

static frig_status read_initial_shape(sp_builder *b) {
    fr_dlib_reader *r = &b->r;
    fr_shape_predictor *sp = b->sp;
    size_t rows;
    if (fr_dlib_read_column_header(r, "the initial shape", 2 * FR_SP_MAX_PARTS, &rows)) return r->status;
    if (rows < 2 || rows % 2) return fr_dlib_corrupt(r, "the initial shape has %zu coordinates (an even number >= 2 expected)", rows);
    sp->parts = (int)(rows / 2);
    b->coords = rows;
    sp->initial_shape = malloc(rows * sizeof *sp->initial_shape);
    sp->initial_centred = malloc(rows * sizeof *sp->initial_centred);
    if (!sp->initial_shape || !sp->initial_centred) return nomem(b);
    if (fr_dlib_read_floats(r, "the initial shape", rows, sp->initial_shape)) return r->status;
    /* Centroid and spread of the initial shape, for the per-cascade similarity fit. */
    double mx = 0, my = 0, ss = 0;
    for (int i = 0; i < sp->parts; i++) {
        mx += sp->initial_shape[2 * i];
        my += sp->initial_shape[2 * i + 1];
    }
    mx /= sp->parts;
    my /= sp->parts;
    for (int i = 0; i < sp->parts; i++) {
        double dx = sp->initial_shape[2 * i] - mx, dy = sp->initial_shape[2 * i + 1] - my;
        sp->initial_centred[2 * i] = dx;
        sp->initial_centred[2 * i + 1] = dy;
        ss += dx * dx + dy * dy;
    }
    if (sp->parts > 1 && !(ss > 0)) return fr_dlib_corrupt(r, "all points of the initial shape coincide");
    sp->initial_mean[0] = mx;
    sp->initial_mean[1] = my;
    sp->initial_sumsq = ss;
    return FRIG_OK;
}

/* One regression tree: its splits, then its leaves (a full binary tree: leaves = splits + 1,
 * a power of two). Split indices are checked against the feature count later, once known. */
static frig_status read_tree(sp_builder *b) {
    fr_dlib_reader *r = &b->r;
    fr_shape_predictor *sp = b->sp;
    size_t n_splits, n_leaves;
    if (fr_dlib_read_count(r, "a tree's splits", 8, ((size_t)1 << FR_SP_MAX_TREE_DEPTH) - 1, &n_splits))
        return r->status;
    if (!reserve((void **)&sp->splits, &b->split_cap, first_need(b, b->split_cap, b->splits + n_splits, n_splits, 8),
                 sizeof *sp->splits))
        return nomem(b);
    for (size_t i = 0; i < n_splits; i++) {
        uint64_t i1, i2;
        float thresh;
        if (fr_dlib_read_uint(r, "a split's first pixel", &i1) || fr_dlib_read_uint(r, "a split's second pixel", &i2) ||
            fr_dlib_read_float(r, "a split threshold", &thresh))
            return r->status;
        if (i1 >= FR_SP_MAX_FEATURES || i2 >= FR_SP_MAX_FEATURES)
            return fr_dlib_corrupt(r, "split %zu uses feature pixel %llu (at most %d pixels allowed)", i,
                                   (unsigned long long)(i1 > i2 ? i1 : i2), FR_SP_MAX_FEATURES);
        fr_sp_split *s = &sp->splits[b->splits + i];
        s->idx1 = (uint16_t)i1;
        s->idx2 = (uint16_t)i2;
        s->thresh = thresh;
    }
    size_t leaf_bytes = 4 + 4 * b->coords; /* a matrix header and the floats, at their smallest */
    if (fr_dlib_read_count(r, "a tree's leaves", leaf_bytes, n_splits + 1, &n_leaves)) return r->status;
    if (n_leaves != n_splits + 1 || (n_leaves & (n_leaves - 1)))
        return fr_dlib_corrupt(r, "a tree with %zu splits has %zu leaves (a full binary tree has splits + 1, a power of 2)",
                               n_splits, n_leaves);
    size_t need = first_need(b, b->leaf_cap, b->leaves + n_leaves, n_leaves, leaf_bytes);
    if (!reserve((void **)&sp->leaves, &b->leaf_cap, need, b->coords * sizeof *sp->leaves))
        return nomem(b);
    for (size_t l = 0; l < n_leaves; l++) {
        size_t rows;
        if (fr_dlib_read_column_header(r, "a leaf", b->coords, &rows)) return r->status;
        if (rows != b->coords)
            return fr_dlib_corrupt(r, "a leaf has %zu values, the shape %zu", rows, b->coords);
        float *leaf = sp->leaves + (b->leaves + l) * b->coords;
        if (fr_dlib_read_floats(r, "a leaf value", rows, leaf)) return r->status;
    }
    b->splits += n_splits;
    b->leaves += n_leaves;
    b->trees++;
    if (!reserve((void **)&sp->split_begin, &b->tree_cap, b->trees + 1, sizeof *sp->split_begin)) return nomem(b);
    sp->split_begin[b->trees] = b->splits;
    return FRIG_OK;
}

static frig_status read_forests(sp_builder *b) {
    fr_dlib_reader *r = &b->r;
    fr_shape_predictor *sp = b->sp;
    size_t n;
    if (fr_dlib_read_count(r, "the cascade count", 2, FR_SP_MAX_CASCADES, &n)) return r->status;
    sp->cascades = (int)n;
    sp->tree_begin = calloc(n + 1, sizeof *sp->tree_begin);
    sp->feature_begin = calloc(n + 1, sizeof *sp->feature_begin);
    if (!sp->tree_begin || !sp->feature_begin) return nomem(b);
    if (!reserve((void **)&sp->split_begin, &b->tree_cap, 1, sizeof *sp->split_begin)) return nomem(b);
    sp->split_begin[0] = 0;
    for (size_t c = 0; c < n; c++) {
        size_t trees;
        if (fr_dlib_read_count(r, "a cascade's tree count", 4, FR_SP_MAX_TREES, &trees)) return r->status;
        if (c == 0) b->trees_expected = n * trees;
        for (size_t t = 0; t < trees; t++)
            if (read_tree(b)) return at_tree(b, c, t);
        sp->tree_begin[c + 1] = b->trees;
    }
    return FRIG_OK;
}

/* Per cascade: the landmark each feature pixel hangs from, then its offset from it. */
static frig_status read_features(sp_builder *b) {
    fr_dlib_reader *r = &b->r;
    fr_shape_predictor *sp = b->sp;
    size_t n;
    if (fr_dlib_read_count(r, "the anchor lists", 2, FR_SP_MAX_CASCADES, &n)) return r->status;
    if (n != (size_t)sp->cascades)
        return fr_dlib_corrupt(r, "%zu anchor lists for %d cascades", n, sp->cascades);
    for (size_t c = 0; c < n; c++) {
        size_t count;
        if (fr_dlib_read_count(r, "a cascade's anchors", 2, FR_SP_MAX_FEATURES, &count)) return r->status;
        if (!reserve((void **)&sp->anchor, &b->feature_cap, b->features + count, sizeof *sp->anchor))
            return nomem(b);
        for (size_t i = 0; i < count; i++) {
            uint64_t a;
            if (fr_dlib_read_uint(r, "an anchor", &a)) return r->status;
            if (a >= (uint64_t)sp->parts)
                return fr_dlib_corrupt(r, "cascade %zu: anchor %llu of a %d-point shape", c, (unsigned long long)a,
                                       sp->parts);
            sp->anchor[b->features + i] = (uint32_t)a;
        }
        b->features += count;
        sp->feature_begin[c + 1] = b->features;
    }
    sp->delta = malloc((b->features ? b->features : 1) * 2 * sizeof *sp->delta);
    if (!sp->delta) return nomem(b);
    if (fr_dlib_read_count(r, "the delta lists", 2, FR_SP_MAX_CASCADES, &n)) return r->status;
    if (n != (size_t)sp->cascades)
        return fr_dlib_corrupt(r, "%zu delta lists for %d cascades", n, sp->cascades);
    for (size_t c = 0; c < n; c++) {
        size_t count, want = sp->feature_begin[c + 1] - sp->feature_begin[c];
        if (fr_dlib_read_count(r, "a cascade's deltas", 8, FR_SP_MAX_FEATURES, &count)) return r->status;
        if (count != want) return fr_dlib_corrupt(r, "cascade %zu: %zu deltas for %zu anchors", c, count, want);
        float *d = sp->delta + 2 * sp->feature_begin[c];
        if (fr_dlib_read_floats(r, "a delta", 2 * count, d)) return r->status;
    }
    return FRIG_OK;
}

/* Every split must compare pixels that its cascade samples. */
static frig_status check_split_indices(sp_builder *b) {
    const fr_shape_predictor *sp = b->sp;
    for (int c = 0; c < sp->cascades; c++) {
        size_t nf = sp->feature_begin[c + 1] - sp->feature_begin[c];
        for (size_t t = sp->tree_begin[c]; t < sp->tree_begin[c + 1]; t++)
            for (size_t s = sp->split_begin[t]; s < sp->split_begin[t + 1]; s++)
                if (sp->splits[s].idx1 >= nf || sp->splits[s].idx2 >= nf)
                    return fr_dlib_corrupt(&b->r, "cascade %d, tree %zu: a split uses feature pixel %u of %zu", c,
                                           t - sp->tree_begin[c],
                                           (unsigned)(sp->splits[s].idx1 > sp->splits[s].idx2 ? sp->splits[s].idx1
                                                                                              : sp->splits[s].idx2),
                                           nf);
    }
    return FRIG_OK;
}

frig_status fr_shape_predictor_parse(frig_ctx *ctx, const char *name, const unsigned char *data, size_t size,
                                     fr_shape_predictor **out) {
    if (!out) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "fr_shape_predictor_parse: no output pointer");
    *out = NULL;
    if (!name) name = "shape predictor";
    if (!data && size) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "%s: no data", name);
    if (size >= 4 && data[0] == 'B' && data[1] == 'Z' && data[2] == 'h' && data[3] >= '0' && data[3] <= '9')
        return fr_error(ctx, FRIG_ERR_CORRUPT, "%s: this is a bzip2-compressed file: decompress it first (bunzip2)",
                        name);
    sp_builder b;
    memset(&b, 0, sizeof b);
    fr_dlib_reader_init(&b.r, ctx, name, data, size);
    b.sp = calloc(1, sizeof *b.sp);
    if (!b.sp) return fr_nomem(ctx, "a shape predictor");
    int64_t version;
    if (!fr_dlib_read_int(&b.r, "the version", 4, &version) && version != 1)
        fr_dlib_corrupt(&b.r, "version %lld where dlib's shape_predictor has version 1", (long long)version);
    if (!b.r.status && !read_initial_shape(&b) && !read_forests(&b) && !read_features(&b)) check_split_indices(&b);
    if (b.r.status) {
        frig_status st = b.r.status;
        fr_shape_predictor_free(b.sp);
        return st;
    }
    if (b.r.pos != size)
        fr_log(ctx, FRIG_LOG_DEBUG, "%s: %zu bytes after the shape predictor ignored", name, size - b.r.pos);
    *out = b.sp;
    return FRIG_OK;
}

frig_status fr_shape_predictor_load(frig_ctx *ctx, const char *path, fr_shape_predictor **out) {
    if (!out) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "fr_shape_predictor_load: no output pointer");
    *out = NULL;
    if (!path) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "fr_shape_predictor_load: no path");
    fr_file_map map;
    frig_status st = fr_file_map_open(ctx, path, FR_SP_MAX_FILE, &map);
    if (st) return st;
    st = fr_shape_predictor_parse(ctx, path, map.data, map.size, out);
    fr_file_map_close(&map);
    return st;
}

void fr_shape_predictor_free(fr_shape_predictor *sp) {
    if (!sp) return;
    free(sp->initial_shape);
    free(sp->initial_centred);
    free(sp->tree_begin);
    free(sp->feature_begin);
    free(sp->split_begin);
    free(sp->splits);
    free(sp->leaves);
    free(sp->anchor);
    free(sp->delta);
    free(sp);
}

int fr_shape_predictor_num_parts(const fr_shape_predictor *sp) { return sp ? sp->parts : 0; }
