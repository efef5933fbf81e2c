/* Import of the ICT-FaceKit light model (Li et al., "Learning Formation of Physically-Based
 * Face Attributes", CVPR 2020): the neutral mesh, 100 identity PCA modes (files = neutral
 * + 1 sigma) and the ARKit-style expression shapes, stored as deltas in metres. */
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include <cJSON.h>

#include "core/context.h"
#include "io/file.h"
#include "model/ict_layout.h"
#include "model/model.h"
#include "model/mtl_reader.h"
#include "model/obj_reader.h"

#define ICT_IDENTITY_COUNT 100
#define MAX_OBJ_FILE ((size_t)1 << 30)
#define CM_PER_M 100.0
#define ERR_SIZE 512

static const char neutral_file[] = "generic_neutral_mesh.obj";
static const char json_file[] = "vertex_indices.json";
/* Shapes in the folder that vertex_indices.json does not list. */
static const char *const extra_expressions[] = {"cheekRaiser_L", "cheekRaiser_R", "PupilDilate_L", "PupilDilate_R"};

typedef struct ict_index {
    int expression_count;
    char **expressions;  /* the JSON's list, then the extras */
    int32_t *fitting;
    int32_t landmarks[FR_LANDMARK_COUNT];
    int rigid_count;
    int32_t *rigid;
} ict_index;

static void index_free(ict_index *x) {
    for (int i = 0; i < x->expression_count; i++) free(x->expressions[i]);
    free(x->expressions);
    free(x->fitting);
    free(x->rigid);
}

static const cJSON *json_array(frig_ctx *ctx, const cJSON *root, const char *path, const char *key, frig_status *s) {
    const cJSON *a = cJSON_GetObjectItemCaseSensitive(root, key);
    if (!cJSON_IsArray(a)) *s = fr_error(ctx, FRIG_ERR_CORRUPT, "%s: no '%s' list", path, key);
    return a;
}

static frig_status json_ints(frig_ctx *ctx, const char *path, const cJSON *a, const char *key, int32_t *out, int n) {
    int i = 0;
    const cJSON *e;
    cJSON_ArrayForEach(e, a) {
        if (!cJSON_IsNumber(e) || e->valuedouble < 0 || e->valuedouble >= FR_ICT_VERTEX_COUNT ||
            e->valuedouble != (double)(int)e->valuedouble)
            return fr_error(ctx, FRIG_ERR_CORRUPT, "%s: '%s' entry %d is not a vertex index below %d", path, key, i,
                            FR_ICT_VERTEX_COUNT);
        out[i++] = (int32_t)e->valuedouble;
    }
    return i == n ? FRIG_OK : fr_error(ctx, FRIG_ERR_CORRUPT, "%s: '%s' has %d entries, expected %d", path, key, i, n);
}

static int listed(const cJSON *a, const char *name) {
    const cJSON *e;
    cJSON_ArrayForEach(e, a) if (cJSON_IsString(e) && strcmp(e->valuestring, name) == 0) return 1;
    return 0;
}

static frig_status add_name(frig_ctx *ctx, const char *path, ict_index *x, const char *name, int fitting) {
    if (!fr_name_is_safe(name))
        return fr_error(ctx, FRIG_ERR_CORRUPT, "%s: expression name '%s' is not a plain file name", path, name);
    for (int i = 0; i < x->expression_count; i++)
        if (strcmp(x->expressions[i], name) == 0) return FRIG_OK;
    x->expressions[x->expression_count] = strdup(name);
    if (!x->expressions[x->expression_count]) return fr_nomem(ctx, "expression names");
    x->fitting[x->expression_count++] = fitting;
    return FRIG_OK;
}

static frig_status parse_index(frig_ctx *ctx, const char *path, const cJSON *root, ict_index *x) {
    frig_status s = FRIG_OK;
    const cJSON *fit = json_array(ctx, root, path, "fitting_expressions", &s);
    const cJSON *expr = cJSON_GetObjectItemCaseSensitive(root, "expressions");
    const cJSON *lm = s ? NULL : json_array(ctx, root, path, "idx_to_landmark_verts", &s);
    const cJSON *rigid = s ? NULL : json_array(ctx, root, path, "idx_to_rigid_verts", &s);
    if (s) return s;
    if (!cJSON_IsArray(expr)) expr = fit;
    int n = cJSON_GetArraySize(expr) + cJSON_GetArraySize(fit) + 4;
    x->expressions = calloc((size_t)n, sizeof *x->expressions);
    x->fitting = calloc((size_t)n, sizeof *x->fitting);
    x->rigid_count = cJSON_GetArraySize(rigid);
    x->rigid = malloc(sizeof *x->rigid * (size_t)(x->rigid_count + 1));
    if (!x->expressions || !x->fitting || !x->rigid) return fr_nomem(ctx, "the model's index lists");
    const cJSON *e;
    cJSON_ArrayForEach(e, expr) {
        if (!cJSON_IsString(e)) return fr_error(ctx, FRIG_ERR_CORRUPT, "%s: an expression name is not a string", path);
        if ((s = add_name(ctx, path, x, e->valuestring, listed(fit, e->valuestring)))) return s;
    }
    cJSON_ArrayForEach(e, fit) {
        if (!cJSON_IsString(e)) return fr_error(ctx, FRIG_ERR_CORRUPT, "%s: a fitting expression is not a string", path);
        if ((s = add_name(ctx, path, x, e->valuestring, 1))) return s;
    }
    for (size_t i = 0; i < sizeof extra_expressions / sizeof extra_expressions[0]; i++)
        if ((s = add_name(ctx, path, x, extra_expressions[i], listed(fit, extra_expressions[i])))) return s;
    if ((s = json_ints(ctx, path, lm, "idx_to_landmark_verts", x->landmarks, FR_LANDMARK_COUNT))) return s;
    return json_ints(ctx, path, rigid, "idx_to_rigid_verts", x->rigid, x->rigid_count);
}

static frig_status read_index(frig_ctx *ctx, const char *dir, ict_index *x) {
    char *path = fr_path_join(dir, json_file);
    if (!path) return fr_nomem(ctx, "a path");
    unsigned char *text;
    size_t size;
    frig_status s = fr_read_file(ctx, path, (size_t)1 << 26, &text, &size);
    if (!s) {
        cJSON *root = cJSON_ParseWithLength((const char *)text, size);
        if (!root) s = fr_error(ctx, FRIG_ERR_CORRUPT, "%s: not valid JSON", path);
        else s = parse_index(ctx, path, root, x);
        cJSON_Delete(root);
        free(text);
    }
    free(path);
    return s;
}

/* Every file the import needs, in the order the model stores them: neutral, identities,
 * expressions. */
typedef struct file_list {
    int count;
    char **paths;
} file_list;

static void files_free(file_list *f) {
    for (int i = 0; i < f->count; i++) free(f->paths[i]);
    free(f->paths);
}

static frig_status list_files(frig_ctx *ctx, const char *dir, const ict_index *x, file_list *f) {
    int n = 1 + ICT_IDENTITY_COUNT + x->expression_count;
    f->paths = calloc((size_t)n, sizeof *f->paths);
    if (!f->paths) return fr_nomem(ctx, "file names");
    f->count = n;
    for (int i = 0; i < n; i++) {
        char name[96];
        if (i == 0) snprintf(name, sizeof name, "%s", neutral_file);
        else if (i <= ICT_IDENTITY_COUNT) snprintf(name, sizeof name, "identity%03d.obj", i - 1);
        else snprintf(name, sizeof name, "%s.obj", x->expressions[i - 1 - ICT_IDENTITY_COUNT]);
        f->paths[i] = fr_path_join(dir, name);
        if (!f->paths[i]) return fr_nomem(ctx, "file names");
        struct stat st;
        if (stat(f->paths[i], &st) != 0 || !S_ISREG(st.st_mode))
            return fr_error(ctx, FRIG_ERR_NOT_FOUND, "%s: missing from the ICT-FaceKit folder (needed for %s)",
                            f->paths[i],
                            i == 0 ? "the neutral mesh" : i <= ICT_IDENTITY_COUNT ? "an identity mode" : "an expression");
    }
    return FRIG_OK;
}

static frig_status read_obj(const char *path, fr_obj *obj, char *err) {
    unsigned char *text;
    size_t size;
    frig_status s = fr_read_file(NULL, path, MAX_OBJ_FILE, &text, &size);
    if (s) {
        snprintf(err, ERR_SIZE, "%s: cannot be read (%s)", path, frig_strerror(s));
        return s;
    }
    s = fr_obj_parse((const char *)text, size, path, obj, err, ERR_SIZE);
    free(text);
    return s;
}

/* One identity or expression file: same vertex count and (if it has faces) the same faces as
 * the neutral; its deltas from the neutral, in metres, go to 'delta'. */
static frig_status read_shape(const char *path, const fr_obj *neutral, float *delta, char *err) {
    fr_obj o;
    frig_status s = read_obj(path, &o, err);
    if (s) return s;
    if (o.vertex_count != neutral->vertex_count) {
        snprintf(err, ERR_SIZE, "%s: %d vertices where %s has %d", path, o.vertex_count, neutral_file,
                 neutral->vertex_count);
        s = FRIG_ERR_CORRUPT;
    } else if (o.polygon_count &&
               (o.polygon_count != neutral->polygon_count || o.corner_count != neutral->corner_count ||
                memcmp(o.offsets, neutral->offsets, sizeof(int32_t) * ((size_t)o.polygon_count + 1)) ||
                memcmp(o.corners, neutral->corners, sizeof(int32_t) * (size_t)o.corner_count))) {
        snprintf(err, ERR_SIZE, "%s: its faces differ from those of %s", path, neutral_file);
        s = FRIG_ERR_CORRUPT;
    } else {
        for (int i = 0; i < 3 * o.vertex_count; i++)
            delta[i] = (float)((o.positions[i] - neutral->positions[i]) / CM_PER_M);
    }
    fr_obj_free(&o);
    return s;
}

/* All identity and expression files, in parallel; the first failure in file order wins. */
static frig_status read_shapes(frig_ctx *ctx, const file_list *f, const fr_obj *neutral, float *identity,
                               float *expressions) {
    int n = f->count - 1;
    size_t n3 = 3 * (size_t)neutral->vertex_count;
    frig_status *status = calloc((size_t)n, sizeof *status);
    char *errors = malloc((size_t)n * ERR_SIZE);
    if (!status || !errors) {
        free(status), free(errors);
        return fr_nomem(ctx, "the import");
    }
    atomic_size_t done = 0;
#pragma omp parallel for schedule(dynamic) num_threads(fr_threads(ctx))
    for (int i = 0; i < n; i++) {
        if (fr_cancelled(ctx)) {
            status[i] = FRIG_ERR_CANCELLED;
            snprintf(errors + (size_t)i * ERR_SIZE, ERR_SIZE, "the import was cancelled");
            continue;
        }
        float *dst = i < ICT_IDENTITY_COUNT ? identity + n3 * (size_t)i
                                            : expressions + n3 * (size_t)(i - ICT_IDENTITY_COUNT);
        status[i] = read_shape(f->paths[i + 1], neutral, dst, errors + (size_t)i * ERR_SIZE);
        fr_progress_tick(ctx, &done, "import", (size_t)n);
    }
    frig_status s = FRIG_OK;
    for (int i = 0; i < n && !s; i++)
        if (status[i]) s = fr_error(ctx, status[i], "%s", errors + (size_t)i * ERR_SIZE);
    free(status);
    free(errors);
    return s;
}

static frig_status read_neutral(frig_ctx *ctx, const char *path, fr_obj *o) {
    char err[ERR_SIZE];
    if (read_obj(path, o, err)) return fr_error(ctx, FRIG_ERR_CORRUPT, "%s", err);
    frig_status s = fr_ict_check_layout(ctx, path, o);
    for (int c = 0; c < o->corner_count && !s; c++)
        if (o->corner_uvs[c] < 0) s = fr_error(ctx, FRIG_ERR_UNSUPPORTED, "%s: a face corner has no texture coordinate", path);
    for (int m = 0; m < o->material_count && !s; m++)
        if (!fr_name_is_safe(o->material_names[m]))
            s = fr_error(ctx, FRIG_ERR_UNSUPPORTED, "%s: material name '%s' is not a plain name", path,
                         o->material_names[m]);
    return s;
}

static void material_colours(const char *dir, const fr_obj *o, float *kd) {
    static const float grey[3] = {0.6f, 0.6f, 0.6f};
    unsigned char *text = NULL;
    size_t size = 0;
    char *path = o->mtllib ? fr_path_join(dir, o->mtllib) : NULL;
    if (path && fr_read_file(NULL, path, (size_t)1 << 24, &text, &size)) text = NULL, size = 0;
    fr_mtl_diffuse(text ? (const char *)text : "", size, (const char *const *)o->material_names, o->material_count,
                   grey, kd);
    free(text);
    free(path);
}

/* The regions and names of the ICT layout table. */
static frig_status layout_regions(frig_ctx *ctx, int32_t *ranges, char **blob, size_t *size) {
    const char *names[64];
    int n = fr_ict_region_count();
    for (int i = 0; i < n; i++) {
        const fr_ict_region *r = fr_ict_region_at(i);
        names[i] = r->name;
        ranges[2 * i] = r->first_vertex;
        ranges[2 * i + 1] = r->last_vertex - r->first_vertex + 1;
    }
    return fr_names_pack(ctx, names, n, blob, size);
}

typedef struct import_state {
    ict_index index;
    file_list files;
    fr_obj neutral;
    float *positions, *identity, *expressions, *kd;
    int32_t *tris, *tri_uvs, *tri_mats, ranges[128];
    char *material_blob, *region_blob, *expression_blob;
} import_state;

static void state_free(import_state *st) {
    index_free(&st->index);
    files_free(&st->files);
    fr_obj_free(&st->neutral);
    free(st->positions), free(st->identity), free(st->expressions), free(st->kd);
    free(st->tris), free(st->tri_uvs), free(st->tri_mats);
    free(st->material_blob), free(st->region_blob), free(st->expression_blob);
}

static frig_status assemble(frig_ctx *ctx, import_state *st, frig_model **out) {
    fr_model_parts p;
    memset(&p, 0, sizeof p);
    const fr_obj *o = &st->neutral;
    fr_topology *t = &p.topo;
    frig_status s;
    if ((s = fr_triangulate(ctx, o->polygon_count, o->offsets, o->corners, o->corner_uvs, o->materials,
                            &t->triangle_count, &st->tris, &st->tri_uvs, &st->tri_mats)) ||
        (s = fr_names_pack(ctx, (const char *const *)o->material_names, o->material_count, &st->material_blob,
                           &t->material_blob_size)) ||
        (s = layout_regions(ctx, st->ranges, &st->region_blob, &t->region_blob_size)) ||
        (s = fr_names_pack(ctx, (const char *const *)st->index.expressions, st->index.expression_count,
                           &st->expression_blob, &p.expression_blob_size)))
        return s;
    t->vertex_count = o->vertex_count, t->polygon_count = o->polygon_count, t->corner_count = o->corner_count;
    t->uv_count = o->uv_count, t->material_count = o->material_count, t->region_count = fr_ict_region_count();
    t->poly_offsets = o->offsets, t->poly_corners = o->corners, t->poly_uvs = o->corner_uvs;
    t->poly_materials = o->materials, t->triangles = st->tris, t->triangle_uvs = st->tri_uvs;
    t->triangle_materials = st->tri_mats, t->regions = st->ranges, t->uvs = o->uvs, t->material_kd = st->kd;
    t->material_blob = st->material_blob, t->region_blob = st->region_blob;
    p.identity_count = ICT_IDENTITY_COUNT, p.expression_count = st->index.expression_count;
    p.landmark_count = FR_LANDMARK_COUNT, p.rigid_count = st->index.rigid_count;
    p.contour_count[0] = fr_ict_contour(0, &p.contour[0]);
    p.contour_count[1] = fr_ict_contour(1, &p.contour[1]);
    p.neutral = st->positions, p.identity = st->identity, p.expressions = st->expressions;
    p.expression_blob = st->expression_blob, p.expression_fitting = st->index.fitting;
    p.landmarks = st->index.landmarks, p.rigid = st->index.rigid;
    return fr_model_build(ctx, &p, out);
}

static frig_status import_into(frig_ctx *ctx, const char *dir, import_state *st, frig_model **out) {
    frig_status s;
    if ((s = read_index(ctx, dir, &st->index)) || (s = list_files(ctx, dir, &st->index, &st->files)) ||
        (s = read_neutral(ctx, st->files.paths[0], &st->neutral)))
        return s;
    size_t n3 = 3 * (size_t)st->neutral.vertex_count;
    st->positions = malloc(sizeof(float) * n3);
    st->identity = malloc(sizeof(float) * n3 * ICT_IDENTITY_COUNT);
    st->expressions = malloc(sizeof(float) * n3 * (size_t)st->index.expression_count);
    st->kd = malloc(sizeof(float) * 3 * (size_t)st->neutral.material_count);
    if (!st->positions || !st->identity || !st->expressions || !st->kd) return fr_nomem(ctx, "the model's shapes");
    for (size_t i = 0; i < n3; i++) st->positions[i] = (float)(st->neutral.positions[i] / CM_PER_M);
    material_colours(dir, &st->neutral, st->kd);
    if ((s = read_shapes(ctx, &st->files, &st->neutral, st->identity, st->expressions))) return s;
    return assemble(ctx, st, out);
}

frig_status frig_model_import_ict(frig_ctx *ctx, const char *dir, frig_model **out) {
    if (!out) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_model_import_ict: out is NULL");
    *out = NULL;
    if (!dir) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_model_import_ict: no folder given");
    struct stat sb;
    if (stat(dir, &sb) != 0 || !S_ISDIR(sb.st_mode))
        return fr_error(ctx, FRIG_ERR_NOT_FOUND, "%s: not an ICT-FaceKit folder (no such folder)", dir);
    import_state st;
    memset(&st, 0, sizeof st);
    frig_status s = import_into(ctx, dir, &st, out);
    state_free(&st);
    return s;
}
