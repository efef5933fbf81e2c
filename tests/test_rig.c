/* The rig: from the model, evaluation, the native file, ARKit names, and the exports read
 * back: OBJ through the OBJ reader, the .glb parsed here (chunks, JSON, accessors, the
 * jawOpen target decoded), PLY bytes. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cJSON.h>

#include "core/context.h"
#include "model/model.h"
#include "model/obj_reader.h"
#include "image/image.h"
#include "image/srgb.h"
#include "mesh/eye_frame.h"
#include "model_fixture.h"
#include "rig/look.h"
#include "rig/rig.h"
#include "testing.h"

static uint32_t u32(const unsigned char *p) {
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

static void test_from_model(frig_ctx *ctx, const frig_model *m, const frig_rig *r, const double *id) {
    int nv = frig_model_vertex_count(m);
    size_t n3 = 3 * (size_t)nv;
    CHECK(frig_rig_vertex_count(r) == nv && frig_rig_shape_count(r) == 57);
    CHECK(strcmp(frig_rig_shape_name(r, 26), frig_model_expression_name(m, 26)) == 0);
    CHECK(frig_rig_shape_find(r, "jawOpen") == frig_model_expression_find(m, "jawOpen"));
    float *a = malloc(sizeof *a * n3), *b = malloc(sizeof *b * n3);
    frig_model_eval(ctx, m, id, NULL, a);
    CHECK(memcmp(a, frig_rig_neutral(r), sizeof *a * n3) == 0);
    CHECK(memcmp(frig_rig_shape_deltas(r, 5), frig_model_expression_deltas(m) + 5 * n3, sizeof *a * n3) == 0);
    double w[57];
    for (int k = 0; k < 57; k++) w[k] = (k % 7) / 7.0;
    CHECK(frig_model_eval(ctx, m, id, w, a) == FRIG_OK);
    CHECK(frig_rig_eval(ctx, r, w, b) == FRIG_OK);
    double worst = 0;
    for (size_t i = 0; i < n3; i++) worst = fmax(worst, fabs(a[i] - b[i]));
    CHECK(worst < 1e-6);
    free(a), free(b);
}

static void test_file(frig_ctx *ctx, const frig_rig *r, const char *tmp) {
    char a[4200], b[4200];
    snprintf(a, sizeof a, "%s/a.frigrig", tmp);
    snprintf(b, sizeof b, "%s/b.frigrig", tmp);
    frig_rig *c = NULL, *l = NULL;
    CHECK(frig_rig_clone(ctx, r, &c) == FRIG_OK);
    size_t n3 = 3 * (size_t)frig_rig_vertex_count(r);
    float *x = malloc(sizeof *x * n3);
    for (size_t i = 0; i < n3; i++) x[i] = frig_rig_neutral(r)[i] * 1.01f;
    CHECK(frig_rig_set_neutral(ctx, c, x) == FRIG_OK);
    CHECK(frig_rig_set_shape_deltas(ctx, c, 3, x) == FRIG_OK);
    CHECK(frig_rig_neutral(r)[0] != frig_rig_neutral(c)[0]); /* the clone is its own */
    x[7] = NAN;
    CHECK(frig_rig_set_neutral(ctx, c, x) == FRIG_ERR_INVALID_ARGUMENT);
    CHECK(frig_rig_set_shape_deltas(ctx, c, 57, x) == FRIG_ERR_INVALID_ARGUMENT);
    CHECK(frig_rig_save(ctx, c, a) == FRIG_OK && frig_rig_load(ctx, a, &l) == FRIG_OK);
    CHECK(l && frig_rig_save(ctx, l, b) == FRIG_OK);
    size_t na, nb;
    unsigned char *da = test_read_file(a, &na), *db = test_read_file(b, &nb);
    CHECK(da && db && na == nb && memcmp(da, db, na) == 0);
    CHECK(l && frig_rig_neutral(l)[0] == frig_rig_neutral(c)[0] && frig_rig_shape_deltas(l, 3)[5] == x[5]);
    printf("rig file: %zu bytes, save -> load -> save byte-identical\n", na);
    /* Truncated, and a model file given as a rig. */
    FILE *fp = fopen(b, "wb");
    fwrite(da, 1, na / 2, fp);
    fclose(fp);
    frig_rig *bad = NULL;
    CHECK(frig_rig_load(ctx, b, &bad) == FRIG_ERR_TRUNCATED && bad == NULL);
    CHECK(frig_rig_load(ctx, fixture_model_path(), &bad) == FRIG_ERR_CORRUPT);
    CHECK(strstr(frig_ctx_errmsg(ctx), "not a libfrig FRIGRIG file") != NULL);
    free(da), free(db), free(x);
    frig_rig_free(c);
    frig_rig_free(l);
}

static void test_arkit(frig_ctx *ctx, const frig_rig *r) {
    CHECK(frig_arkit_name_count() == 52);
    CHECK(strcmp(frig_arkit_name(0), "eyeBlinkLeft") == 0 && strcmp(frig_arkit_name(51), "tongueOut") == 0);
    CHECK(frig_arkit_name(52) == NULL);
    CHECK(strcmp(frig_rig_arkit_name(r, frig_rig_shape_find(r, "eyeBlink_L")), "eyeBlinkLeft") == 0);
    CHECK(strcmp(frig_rig_arkit_name(r, frig_rig_shape_find(r, "mouthLowerDown_R")), "mouthLowerDownRight") == 0);
    CHECK(strcmp(frig_rig_arkit_name(r, frig_rig_shape_find(r, "browInnerUp_R")), "browInnerUp") == 0);
    CHECK(strcmp(frig_rig_arkit_name(r, frig_rig_shape_find(r, "cheekPuff_L")), "cheekPuff") == 0);
    CHECK(strcmp(frig_rig_arkit_name(r, frig_rig_shape_find(r, "jawOpen")), "jawOpen") == 0);
    CHECK(strcmp(frig_rig_arkit_name(r, frig_rig_shape_find(r, "cheekRaiser_L")), "cheekRaiser_L") == 0);
    int provided = 0;
    for (int i = 0; i < 52; i++) provided += frig_rig_provides_arkit(r, frig_arkit_name(i));
    CHECK(provided == 51 && !frig_rig_provides_arkit(r, "tongueOut") && frig_rig_provides_arkit(r, "cheekPuff"));
    CHECK(frig_rig_target_count(r) == 55);
    CHECK(strcmp(frig_rig_target_name(r, 43), "browInnerUp") == 0 && strcmp(frig_rig_target_name(r, 54), "PupilDilate_R") == 0);
    fr_export_shapes e;
    CHECK(fr_export_shapes_make(ctx, r, &e) == FRIG_OK);
    CHECK(e.count == 55);
    size_t n3 = 3 * (size_t)frig_rig_vertex_count(r);
    const float *bl = frig_rig_shape_deltas(r, frig_rig_shape_find(r, "browInnerUp_L"));
    const float *br = frig_rig_shape_deltas(r, frig_rig_shape_find(r, "browInnerUp_R"));
    int sums = 1;
    for (size_t i = 0; i < n3; i++) sums &= e.deltas[43 * n3 + i] == bl[i] + br[i];
    CHECK(sums && strcmp(e.names[43], "browInnerUp") == 0);
    for (int t = 0; t < e.count; t++) CHECK(strcmp(e.names[t], frig_rig_target_name(r, t)) == 0);
    fr_export_shapes_free(&e);
}

/* Re-read neutral.obj, jawOpen.obj and browInnerUp.obj with the OBJ reader. */
static void test_obj(frig_ctx *ctx, const frig_rig *r, const char *dir) {
    CHECK(frig_rig_save_obj(ctx, r, dir) == FRIG_OK);
    const fr_topology *t = &r->topo;
    size_t n3 = 3 * (size_t)t->vertex_count;
    const char *names[] = {"neutral", "jawOpen", "browInnerUp"};
    for (int f = 0; f < 3; f++) {
        char path[4200];
        snprintf(path, sizeof path, "%s/%s.obj", dir, names[f]);
        size_t size;
        unsigned char *text = test_read_file(path, &size);
        fr_obj o;
        char err[512];
        CHECK(text && fr_obj_parse((const char *)text, size, path, &o, err, sizeof err) == FRIG_OK);
        free(text);
        CHECK(o.vertex_count == t->vertex_count && o.polygon_count == t->polygon_count && o.uv_count == t->uv_count);
        CHECK(memcmp(o.corners, t->poly_corners, sizeof(int32_t) * (size_t)t->corner_count) == 0);
        CHECK(memcmp(o.corner_uvs, t->poly_uvs, sizeof(int32_t) * (size_t)t->corner_count) == 0);
        CHECK(memcmp(o.materials, t->poly_materials, sizeof(int32_t) * (size_t)t->polygon_count) == 0);
        CHECK(o.mtllib && strcmp(o.mtllib, "frig.mtl") == 0);
        double worst = 0;
        for (size_t i = 0; i < n3; i++) {
            double want = r->neutral[i];
            if (f == 1) want += frig_rig_shape_deltas(r, frig_rig_shape_find(r, "jawOpen"))[i];
            if (f == 2)
                want += (double)frig_rig_shape_deltas(r, frig_rig_shape_find(r, "browInnerUp_L"))[i] +
                        frig_rig_shape_deltas(r, frig_rig_shape_find(r, "browInnerUp_R"))[i];
            worst = fmax(worst, fabs(o.positions[i] - want));
        }
        printf("OBJ %s re-read: max error %.2g m\n", names[f], worst);
        CHECK(worst < 1e-7);
        fr_obj_free(&o);
    }
}

typedef struct glb {
    unsigned char *file;
    size_t size;
    cJSON *json;
    const unsigned char *bin;
    size_t bin_size;
} glb;

static const cJSON *item(const cJSON *o, const char *k) { return cJSON_GetObjectItemCaseSensitive(o, k); }
static int num(const cJSON *o, const char *k) { return (int)cJSON_GetNumberValue(item(o, k)); }

/* Accessor a as 'count' VEC3 floats (dense, sparse or all zero) into out. */
static void read_vec3(const glb *g, int a, float *out, int count) {
    const cJSON *acc = cJSON_GetArrayItem(item(g->json, "accessors"), a);
    const cJSON *views = item(g->json, "bufferViews");
    CHECK(num(acc, "count") == count && strcmp(item(acc, "type")->valuestring, "VEC3") == 0);
    memset(out, 0, sizeof *out * 3 * (size_t)count);
    if (item(acc, "bufferView")) {
        const cJSON *v = cJSON_GetArrayItem(views, num(acc, "bufferView"));
        CHECK(num(v, "byteLength") == 12 * count);
        memcpy(out, g->bin + num(v, "byteOffset"), 12 * (size_t)count);
    }
    const cJSON *sp = item(acc, "sparse");
    if (sp) {
        int n = num(sp, "count"), wide = num(item(sp, "indices"), "componentType") == 5125;
        const cJSON *iv = cJSON_GetArrayItem(views, num(item(sp, "indices"), "bufferView"));
        const cJSON *vv = cJSON_GetArrayItem(views, num(item(sp, "values"), "bufferView"));
        const unsigned char *ip = g->bin + num(iv, "byteOffset"), *vp = g->bin + num(vv, "byteOffset");
        for (int i = 0; i < n; i++) {
            uint32_t k = wide ? u32(ip + 4 * i) : (uint32_t)(ip[2 * i] | ip[2 * i + 1] << 8);
            CHECK(k < (uint32_t)count);
            if (k < (uint32_t)count) memcpy(out + 3 * k, vp + 12 * (size_t)i, 12);
        }
    }
    /* min/max are those of the data. */
    const cJSON *mn = item(acc, "min"), *mx = item(acc, "max");
    CHECK(mn && mx);
    for (int d = 0; d < 3 && mn && mx; d++) {
        float lo = out[d], hi = out[d];
        for (int i = 0; i < count; i++) lo = fminf(lo, out[3 * i + d]), hi = fmaxf(hi, out[3 * i + d]);
        CHECK((float)cJSON_GetArrayItem(mn, d)->valuedouble == lo && (float)cJSON_GetArrayItem(mx, d)->valuedouble == hi);
    }
}

static int parse_glb(const char *path, glb *g) {
    memset(g, 0, sizeof *g);
    g->file = test_read_file(path, &g->size);
    if (!g->file || g->size < 28) return 0;
    CHECK(u32(g->file) == 0x46546C67u && u32(g->file + 4) == 2 && u32(g->file + 8) == g->size);
    uint32_t jlen = u32(g->file + 12);
    CHECK(u32(g->file + 16) == 0x4E4F534Au && jlen % 4 == 0);
    g->json = cJSON_ParseWithLength((const char *)g->file + 20, jlen);
    g->bin = g->file + 20 + jlen + 8;
    g->bin_size = u32(g->file + 20 + jlen);
    CHECK(u32(g->file + 20 + jlen + 4) == 0x004E4942u && 28 + jlen + g->bin_size == g->size);
    return g->json != NULL;
}

/* The expected primitive vertices: first every vertex the material's triangles use, in ICT's
 * order, with the UV of its first corner; then the other (vertex, uv) pairs in order of first
 * use. Returns the count; *first gets how many come first. */
static int expected_vertices(const fr_topology *t, int material, int32_t *vmap, int32_t *uvmap, int *first) {
    int32_t *first_uv = malloc(sizeof *first_uv * (size_t)t->vertex_count);
    for (int v = 0; v < t->vertex_count; v++) first_uv[v] = -1;
    for (int i = 0; i < t->triangle_count; i++)
        for (int c = 0; t->triangle_materials[i] == material && c < 3; c++)
            if (first_uv[t->triangles[3 * i + c]] < 0) first_uv[t->triangles[3 * i + c]] = t->triangle_uvs[3 * i + c];
    int n = 0;
    for (int v = 0; v < t->vertex_count; v++)
        if (first_uv[v] >= 0) vmap[n] = v, uvmap[n] = first_uv[v], n++;
    *first = n;
    for (int i = 0; i < t->triangle_count; i++) {
        if (t->triangle_materials[i] != material) continue;
        for (int c = 0; c < 3; c++) {
            int32_t v = t->triangles[3 * i + c], uv = t->triangle_uvs[3 * i + c], j;
            if (uv == first_uv[v]) continue;
            for (j = *first; j < n && !(vmap[j] == v && uvmap[j] == uv); j++) {}
            if (j == n) vmap[n] = v, uvmap[n] = uv, n++;
        }
    }
    free(first_uv);
    return n;
}

/* A material by name (NULL when absent) and the PNG bytes of its base-colour texture. */
static const cJSON *material(const glb *g, const char *name) {
    const cJSON *m;
    cJSON_ArrayForEach(m, item(g->json, "materials")) if (strcmp(item(m, "name")->valuestring, name) == 0) return m;
    return NULL;
}

static const unsigned char *material_png(const glb *g, const char *name, size_t *size) {
    const cJSON *m = material(g, name), *tex = item(item(item(m, "pbrMetallicRoughness"), "baseColorTexture"), "index");
    if (!tex) return NULL;
    const cJSON *texture = cJSON_GetArrayItem(item(g->json, "textures"), (int)tex->valuedouble);
    const cJSON *image = cJSON_GetArrayItem(item(g->json, "images"), num(texture, "source"));
    const cJSON *view = cJSON_GetArrayItem(item(g->json, "bufferViews"), num(image, "bufferView"));
    CHECK(strcmp(item(image, "mimeType")->valuestring, "image/png") == 0);
    *size = (size_t)num(view, "byteLength");
    return g->bin + num(view, "byteOffset");
}

static const char *alpha_mode(const glb *g, const char *name) {
    const cJSON *a = item(material(g, name), "alphaMode");
    return a ? a->valuestring : "OPAQUE";
}

/* Painted eyes: sclera masked (its cornea shows the iris), the overlays and lashes blended,
 * every painted texture a PNG. */
static void test_gltf_materials(const glb *g) {
    static const char *const painted[] = {"M_ScleraLeft", "M_ScleraRight", "M_IrisLeft",   "M_IrisRight",
                                          "M_EyeBlend",   "M_EyeOcclusion", "M_EyeLashes"};
    for (size_t i = 0; i < sizeof painted / sizeof painted[0]; i++) {
        size_t n = 0;
        const unsigned char *png = material_png(g, painted[i], &n);
        CHECK(png && n > 100 && memcmp(png, "\x89PNG\r\n\x1a\n", 8) == 0);
    }
    CHECK(strcmp(alpha_mode(g, "M_ScleraLeft"), "MASK") == 0 && strcmp(alpha_mode(g, "M_IrisLeft"), "OPAQUE") == 0);
    CHECK(strcmp(alpha_mode(g, "M_LacrimalFluid"), "BLEND") == 0 && strcmp(alpha_mode(g, "M_EyeOcclusion"), "BLEND") == 0);
    CHECK(strcmp(alpha_mode(g, "M_EyeBlend"), "BLEND") == 0 && strcmp(alpha_mode(g, "M_EyeLashes"), "BLEND") == 0);
    CHECK(strcmp(alpha_mode(g, "M_Face"), "OPAQUE") == 0);
}

static void test_gltf(frig_ctx *ctx, const frig_rig *r, const char *tmp) {
    char a[4200], b[4200];
    snprintf(a, sizeof a, "%s/rig.glb", tmp);
    snprintf(b, sizeof b, "%s/again.glb", tmp);
    CHECK(frig_rig_save_gltf(ctx, r, a) == FRIG_OK && frig_rig_save_gltf(ctx, r, b) == FRIG_OK);
    glb g;
    if (!parse_glb(a, &g)) {
        CHECK(!"glb parses");
        return;
    }
    size_t nb;
    unsigned char *again = test_read_file(b, &nb);
    CHECK(again && nb == g.size && memcmp(again, g.file, nb) == 0); /* deterministic bytes */
    free(again);
    CHECK(strcmp(item(item(g.json, "asset"), "version")->valuestring, "2.0") == 0);
    const cJSON *mesh = cJSON_GetArrayItem(item(g.json, "meshes"), 0);
    const cJSON *names = item(item(mesh, "extras"), "targetNames");
    CHECK(cJSON_GetArraySize(names) == 55 && cJSON_GetArraySize(item(mesh, "weights")) == 55);
    for (int i = 0; i < cJSON_GetArraySize(names); i++)
        CHECK(strcmp(cJSON_GetArrayItem(names, i)->valuestring, frig_rig_target_name(r, i)) == 0);
    int jaw = 17;
    CHECK(strcmp(cJSON_GetArrayItem(names, jaw)->valuestring, "jawOpen") == 0);
    const cJSON *prims = item(mesh, "primitives");
    CHECK(cJSON_GetArraySize(prims) == 12);
    const fr_topology *t = &r->topo;
    int32_t *vmap = malloc(sizeof *vmap * 3 * (size_t)t->triangle_count), *uvmap = malloc(sizeof *uvmap * 3 * (size_t)t->triangle_count);
    float *pos = malloc(sizeof *pos * 9 * (size_t)t->triangle_count), *d = malloc(sizeof *d * 9 * (size_t)t->triangle_count);
    const float *jd = frig_rig_shape_deltas(r, frig_rig_shape_find(r, "jawOpen"));
    int triangles = 0, vertices = 0, mismatches = 0, order_errors = 0;
    const cJSON *p;
    cJSON_ArrayForEach(p, prims) {
        int mat = num(p, "material");
        const char *mname = item(cJSON_GetArrayItem(item(g.json, "materials"), mat), "name")->valuestring;
        int m = 0;
        while (m < t->material_count && strcmp(t->material_names[m], mname) != 0) m++;
        int first, n = expected_vertices(t, m, vmap, uvmap, &first);
        const cJSON *attr = item(p, "attributes");
        /* ICT's vertices first, in ICT's order; extras map every vertex to its ICT index */
        const cJSON *ex = item(p, "extras"), *map = item(ex, "ictVertexIndex");
        CHECK(num(ex, "ictVertexCount") == first && cJSON_GetArraySize(map) == n);
        for (int i = 0; i < n && i < cJSON_GetArraySize(map); i++) order_errors += (int)cJSON_GetArrayItem(map, i)->valuedouble != vmap[i];
        for (int i = 1; i < first; i++) order_errors += vmap[i] <= vmap[i - 1];
        const cJSON *idx = cJSON_GetArrayItem(item(g.json, "accessors"), num(p, "indices"));
        triangles += num(idx, "count") / 3;
        vertices += n;
        CHECK(cJSON_GetArraySize(item(p, "targets")) == 55);
        read_vec3(&g, num(attr, "POSITION"), pos, n);
        read_vec3(&g, num(cJSON_GetArrayItem(item(p, "targets"), jaw), "POSITION"), d, n);
        for (int i = 0; i < n; i++)
            for (int k = 0; k < 3; k++)
                mismatches += pos[3 * i + k] != r->neutral[3 * vmap[i] + k] || d[3 * i + k] != jd[3 * vmap[i] + k];
    }
    printf("glb: %zu bytes, %d primitives, %d triangles, %d vertices, %d mismatching jawOpen values, %d vertex "
           "order errors\n",
           g.size, cJSON_GetArraySize(prims), triangles, vertices, mismatches, order_errors);
    CHECK(triangles == t->triangle_count && mismatches == 0 && order_errors == 0);
    test_gltf_materials(&g);
    free(vmap), free(uvmap), free(pos), free(d);
    cJSON_Delete(g.json);
    free(g.file);
}

/* The eye textures libfrig paints, read at the UVs of known vertices: the iris is dark at the
 * pupil (the vertex nearest the gaze axis) and iris-coloured half-way out; the sclera is clear
 * over the cornea's apex and opaque behind the eye. */
static void test_eye_textures(frig_ctx *ctx, const frig_rig *r) {
    fr_rig_look look;
    CHECK(fr_rig_look_make(ctx, r, &look) == FRIG_OK);
    const fr_topology *t = &r->topo;
    int iris = fr_topology_material(t, "M_IrisLeft"), sclera = fr_topology_material(t, "M_ScleraLeft");
    CHECK(iris >= 0 && sclera >= 0 && look.materials[iris].texture >= 0 && look.materials[sclera].texture >= 0);
    if (iris < 0 || sclera < 0 || look.materials[iris].texture < 0 || look.materials[sclera].texture < 0) return;
    double c[3], a[3];
    CHECK(fr_eye_frame(t, r->neutral, "eyeball_left", c, a));
    /* per material: the uv of the vertex with the largest "along" (the apex; for the iris the front
     * vertex nearest the axis), and of the front vertex closest to half the iris radius (2.9 mm)
     * from the axis */
    for (int pass = 0; pass < 2; pass++) {
        int m = pass ? sclera : iris, apex_uv = -1, mid_uv = -1, back_uv = -1;
        double best_along = -1, best_mid = 1, best_back = 1, best_r = 1;
        for (int i = 0; i < t->triangle_count; i++) {
            if (t->triangle_materials[i] != m) continue;
            for (int k = 0; k < 3; k++) {
                const float *p = r->neutral + 3 * (size_t)t->triangles[3 * i + k];
                double d[3] = {p[0] - c[0], p[1] - c[1], p[2] - c[2]}, along = d[0] * a[0] + d[1] * a[1] + d[2] * a[2];
                double rr = sqrt(fmax(0, d[0] * d[0] + d[1] * d[1] + d[2] * d[2] - along * along));
                if (pass && along > best_along) best_along = along, apex_uv = t->triangle_uvs[3 * i + k];
                if (!pass && along > 0.008 && rr < best_r) best_r = rr, apex_uv = t->triangle_uvs[3 * i + k];
                if (along > 0.008 && fabs(rr - 0.0029) < best_mid) best_mid = fabs(rr - 0.0029), mid_uv = t->triangle_uvs[3 * i + k];
                if (along < best_back) best_back = along, back_uv = t->triangle_uvs[3 * i + k];
            }
        }
        const fr_texture *tex = &look.textures[look.materials[m].texture];
        double apex[4], mid[4], back[4];
        fr_texture_sample(tex, t->uvs[2 * apex_uv], t->uvs[2 * apex_uv + 1], apex);
        fr_texture_sample(tex, t->uvs[2 * mid_uv], t->uvs[2 * mid_uv + 1], mid);
        fr_texture_sample(tex, t->uvs[2 * back_uv], t->uvs[2 * back_uv + 1], back);
        printf("%s texture: apex rgba %.2f %.2f %.2f %.2f, mid-iris %.2f %.2f %.2f, back alpha %.2f\n",
               pass ? "sclera" : "iris", apex[0], apex[1], apex[2], apex[3], mid[0], mid[1], mid[2], back[3]);
        if (!pass) {
            CHECK(apex[0] < 0.1 && apex[1] < 0.1 && apex[2] < 0.1); /* pupil */
            CHECK(mid[0] > 0.2 && mid[0] > mid[2] + 0.08);           /* brown iris */
        } else {
            CHECK(apex[3] < 0.01 && back[3] > 0.99 && back[0] > 0.6); /* clear cornea, white opaque sclera */
        }
    }
    fr_rig_look_free(&look);
}

/* The back of the head continues the face texture: at every vertex M_Face and M_BackHead share,
 * the head's texture shows the colour the face's shows there (linear light, both read as the
 * renderer reads them), although that colour varies along the seam (a flat colour cannot pass);
 * away from the seam it stays within the seam's range (the harmonic extension's maximum principle,
 * up to the cotangent weights' overshoot). */
static void test_head_texture(frig_ctx *ctx, const frig_rig *r) {
    fr_rig_look look;
    CHECK(fr_rig_look_make(ctx, r, &look) == FRIG_OK);
    const fr_topology *t = &r->topo;
    int face = fr_topology_material(t, "M_Face"), head = fr_topology_material(t, "M_BackHead");
    CHECK(face >= 0 && head >= 0 && look.materials[face].texture >= 0 && look.materials[head].texture >= 0);
    if (face < 0 || head < 0 || look.materials[face].texture < 0 || look.materials[head].texture < 0) {
        fr_rig_look_free(&look);
        return;
    }
    const fr_texture *ft = &look.textures[look.materials[face].texture], *ht = &look.textures[look.materials[head].texture];
    float decode[256];
    fr_srgb_decode_table(decode);
    int nv = t->vertex_count;
    int *face_uv = malloc(sizeof(int) * (size_t)nv), *head_uv = malloc(sizeof(int) * (size_t)nv);
    for (int v = 0; v < nv; v++) face_uv[v] = head_uv[v] = -1;
    for (int i = 0; i < t->triangle_count; i++)
        for (int c = 0; c < 3; c++) {
            int v = t->triangles[3 * i + c];
            if (t->triangle_materials[i] == face) face_uv[v] = t->triangle_uvs[3 * i + c];
            if (t->triangle_materials[i] == head) head_uv[v] = t->triangle_uvs[3 * i + c];
        }
    double worst = 0, sum = 0, lo = 1, hi = 0, off_lo = 1, off_hi = 0;
    int n = 0;
    for (int v = 0; v < nv; v++) {
        if (head_uv[v] < 0) continue;
        double hc[4], fc[4];
        fr_texture_sample_linear(ht, decode, t->uvs[2 * head_uv[v]], t->uvs[2 * head_uv[v] + 1], hc);
        if (face_uv[v] < 0) {
            off_lo = fmin(off_lo, hc[0]), off_hi = fmax(off_hi, hc[0]);
            continue;
        }
        fr_texture_sample_linear(ft, decode, t->uvs[2 * face_uv[v]], t->uvs[2 * face_uv[v] + 1], fc);
        for (int k = 0; k < 3; k++) worst = fmax(worst, fabs(hc[k] - fc[k])), sum += fabs(hc[k] - fc[k]);
        lo = fmin(lo, fc[0]), hi = fmax(hi, fc[0]);
        n++;
    }
    printf("head texture: %d seam vertices, red along the seam %.3f-%.3f (elsewhere %.3f-%.3f), "
           "head against face mean %.4f worst %.4f\n", n, lo, hi, off_lo, off_hi, n ? sum / (3 * n) : 0, worst);
    CHECK(n > 100 && hi - lo > 0.3);
    CHECK(n && sum / (3 * n) < 0.01 && worst < 0.05);
    CHECK(off_lo > lo - 0.02 && off_hi < hi + 0.02);
    free(face_uv), free(head_uv);
    fr_rig_look_free(&look);
}

/* export.eye_overlays 0 leaves the three overlays out of glTF and OBJ (their vertices stay);
 * a face texture is embedded byte for byte, copied beside the OBJ files and named in the MTL. */
static void test_options(frig_ctx *ctx, const frig_rig *r0, const char *tmp) {
    frig_rig *r = NULL;
    CHECK(frig_rig_clone(ctx, r0, &r) == FRIG_OK);
    if (!r) return;
    /* a 64 x 32 PNG made here */
    uint8_t px[64 * 32 * 3];
    for (int i = 0; i < 64 * 32; i++) px[3 * i] = (uint8_t)(4 * (i % 64)), px[3 * i + 1] = (uint8_t)(8 * (i / 64)), px[3 * i + 2] = 90;
    unsigned char *png = NULL;
    size_t png_size = 0;
    CHECK(fr_png_encode_pixels(ctx, 64, 32, 3, 64 * 3, px, &png, &png_size) == FRIG_OK);
    char path[8400], glbp[4200], dir[4200];
    snprintf(path, sizeof path, "%s/albedo.png", tmp);
    snprintf(glbp, sizeof glbp, "%s/rig.glb", tmp);
    snprintf(dir, sizeof dir, "%s/shapes", tmp);
    FILE *fp = fopen(path, "wb");
    fwrite(png, 1, png_size, fp);
    fclose(fp);
    char bad[4200];
    snprintf(bad, sizeof bad, "%s/nothing.png", tmp);
    CHECK(frig_rig_set_face_texture(ctx, r, bad) == FRIG_ERR_NOT_FOUND && !frig_rig_has_face_texture(r));
    snprintf(bad, sizeof bad, "%s/rig.glb", tmp);
    fp = fopen(bad, "wb");
    fputs("not a png at all", fp);
    fclose(fp);
    CHECK(frig_rig_set_face_texture(ctx, r, bad) == FRIG_ERR_UNSUPPORTED && strstr(frig_ctx_errmsg(ctx), "PNG"));
    CHECK(frig_rig_set_face_texture(ctx, r, path) == FRIG_OK && frig_rig_has_face_texture(r));
    frig_rig *c = NULL;
    CHECK(frig_rig_clone(ctx, r, &c) == FRIG_OK && frig_rig_has_face_texture(c));
    frig_rig_free(c);
    frig_param ov;
    CHECK(frig_param_lookup(ctx, "export.eye_overlays", &ov) == FRIG_OK);
    CHECK(frig_ctx_set_param(ctx, ov, 0) == FRIG_OK);
    CHECK(frig_rig_save_gltf(ctx, r, glbp) == FRIG_OK && frig_rig_save_obj(ctx, r, dir) == FRIG_OK);
    CHECK(frig_ctx_set_param(ctx, ov, 1) == FRIG_OK);
    glb g;
    if (parse_glb(glbp, &g)) {
        CHECK(cJSON_GetArraySize(item(cJSON_GetArrayItem(item(g.json, "meshes"), 0), "primitives")) == 9);
        CHECK(!material(&g, "M_LacrimalFluid") && !material(&g, "M_EyeBlend") && !material(&g, "M_EyeOcclusion"));
        size_t n = 0;
        const unsigned char *face = material_png(&g, "M_Face", &n);
        CHECK(face && n == png_size && memcmp(face, png, n) == 0);
        const cJSON *f = cJSON_GetArrayItem(item(item(material(&g, "M_Face"), "pbrMetallicRoughness"), "baseColorFactor"), 0);
        CHECK(f && f->valuedouble == 1.0);
        /* the back of the head gets a texture of its own (its colours: test_head_texture) */
        size_t nh = 0;
        CHECK(material_png(&g, "M_BackHead", &nh) && nh > 0);
        const cJSON *hb = item(item(material(&g, "M_BackHead"), "pbrMetallicRoughness"), "baseColorFactor");
        CHECK(hb && cJSON_GetArrayItem(hb, 0)->valuedouble == 1.0);
        cJSON_Delete(g.json);
        free(g.file);
    } else {
        CHECK(!"the glb parses");
    }
    test_head_texture(ctx, r);
    snprintf(path, sizeof path, "%s/frig_face.png", dir);
    size_t n;
    unsigned char *copy = test_read_file(path, &n);
    CHECK(copy && n == png_size && memcmp(copy, png, n) == 0);
    free(copy);
    snprintf(path, sizeof path, "%s/frig.mtl", dir);
    char *mtl = (char *)test_read_file(path, &n);
    CHECK(mtl && strstr(mtl, "newmtl M_Face\nKd 1 1 1\n") && strstr(mtl, "map_Kd frig_face.png") &&
          strstr(mtl, "map_d frig_sclera_left.png") && !strstr(mtl, "M_EyeOcclusion"));
    free(mtl);
    snprintf(path, sizeof path, "%s/neutral.obj", dir);
    char *obj = (char *)test_read_file(path, &n);
    CHECK(obj && !strstr(obj, "usemtl M_LacrimalFluid") && strstr(obj, "usemtl M_EyeLashes"));
    int v = 0;
    /* one pass (ASan's strstr measures the rest of the text at every call: quadratic) */
    for (size_t i = 0; obj && i + 3 <= n; i++) v += obj[i] == '\n' && obj[i + 1] == 'v' && obj[i + 2] == ' ';
    CHECK(v == r->topo.vertex_count); /* every ICT vertex is still there */
    free(obj);
    free(png);
    frig_rig_free(r);
}

static void test_ply(frig_ctx *ctx, const char *tmp) {
    char path[4200];
    snprintf(path, sizeof path, "%s/cloud.ply", tmp);
    float xyz[6] = {1, 2, 3, -1, 0.5f, 0}, n[6] = {0, 0, 1, 1, 0, 0}, c[2] = {0.25f, 1};
    CHECK(frig_save_ply(ctx, path, 2, xyz, n, c) == FRIG_OK);
    size_t size;
    unsigned char *b = test_read_file(path, &size);
    const char *end = b ? strstr((const char *)b, "end_header\n") : NULL;
    CHECK(end && strstr((const char *)b, "format binary_little_endian 1.0\n") &&
          strstr((const char *)b, "element vertex 2\n") && strstr((const char *)b, "property float confidence\n"));
    if (end) {
        size_t h = (size_t)(end - (const char *)b) + 11;
        CHECK(size == h + 2 * 7 * 4);
        float v[14];
        memcpy(v, b + h, sizeof v);
        CHECK(v[0] == 1 && v[5] == 1 && v[6] == 0.25f && v[7] == -1 && v[13] == 1);
    }
    free(b);
    CHECK(frig_save_ply(ctx, path, 2, xyz, NULL, NULL) == FRIG_OK);
    b = test_read_file(path, &size);
    CHECK(b && !strstr((const char *)b, "nx") && size == (size_t)(strstr((const char *)b, "end_header\n") - (char *)b) + 11 + 24);
    free(b);
}

int main(void) {
    frig_ctx *ctx = frig_ctx_create();
    test_ply(ctx, test_temp_dir("rig_ply"));
    frig_model *m = fixture_model(ctx);
    if (!m) {
        frig_ctx_free(ctx);
        return test_skip("no ICT-FaceKit model (../shared/ict-facekit)");
    }
    double id[100] = {0};
    id[0] = 1.5, id[7] = -2, id[99] = 0.5;
    frig_rig *r = NULL;
    CHECK(frig_rig_from_model(ctx, m, id, &r) == FRIG_OK);
    if (r) {
        test_from_model(ctx, m, r, id);
        frig_model_free(m); /* the rig stands alone */
        m = NULL;
        test_file(ctx, r, test_temp_dir("rig_file"));
        test_arkit(ctx, r);
        test_obj(ctx, r, test_temp_dir("rig_obj"));
        test_gltf(ctx, r, test_temp_dir("rig_gltf"));
        test_eye_textures(ctx, r);
        test_options(ctx, r, test_temp_dir("rig_options"));
    }
    frig_rig_free(r);
    frig_model_free(m);
    frig_ctx_free(ctx);
    return test_result("test_rig");
}
