/* glTF 2.0 binary (.glb) export of a rig (Khronos glTF 2.0 specification, sections 3.6
 * "Geometry" with morph targets, 3.8-3.9 materials and textures, 4.4 "GLB File Format"): one
 * mesh, one primitive per material, one morph target per ARKit-named shape (POSITION and
 * NORMAL deltas, sparse where most vertices stay put), mesh.extras.targetNames. In each
 * primitive the ICT vertices it uses come first in ICT's order, UV-seam copies after them,
 * and primitive.extras.ictVertexIndex maps every vertex to its ICT index. Materials and
 * textures come from the rig's look (look.c): painted eyes, the translucent overlays
 * alpha-blended (or left out), the face's base-colour texture. Bytes are deterministic. */
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "io/buffer.h"
#include "io/file.h"
#include "rig/look.h"
#include "rig/rig.h"

enum { GL_UNSIGNED_SHORT = 5123, GL_UNSIGNED_INT = 5125, GL_FLOAT = 5126 };
enum { GL_ARRAY_BUFFER = 34962, GL_ELEMENT_ARRAY_BUFFER = 34963 };

/* One primitive: the triangles of one material, over its own vertices (distinct
 * (vertex, uv) pairs, in order of first use). */
typedef struct prim {
    int material;
    int vertex_count, index_count;
    int ict_count;   /* the first ict_count vertices are distinct ICT vertices in ICT's order */
    int32_t *vertex; /* rig vertex of each glTF vertex */
    int32_t *uv;     /* rig uv of each glTF vertex */
    uint32_t *indices;
} prim;

typedef struct writer {
    frig_ctx *ctx;
    const frig_rig *rig;
    fr_export_shapes shapes;
    float *normals;       /* neutral's, 3 per rig vertex */
    float *normal_deltas; /* per shape, 3 per rig vertex */
    int prim_count;
    prim *prims;
    fr_buffer bin, accessors, views;
    int accessor_count, view_count;
    fr_rig_look look;
} writer;

static void prims_free(writer *w) {
    for (int i = 0; i < w->prim_count; i++) {
        free(w->prims[i].vertex);
        free(w->prims[i].uv);
        free(w->prims[i].indices);
    }
    free(w->prims);
}

/* Vertices of one material's triangles: first every ICT vertex the triangles use, in ICT's
 * order, with the UV of its first corner; then, in order of first use, a copy for each other
 * UV a vertex has (the seams). Copies of vertex v chain from head[v] through next[]. */
static frig_status build_prim(writer *w, int material, int32_t *head, int32_t *next, prim *p) {
    const fr_topology *t = &w->rig->topo;
    int n = 0;
    for (int i = 0; i < t->triangle_count; i++) n += t->triangle_materials[i] == material;
    p->material = material;
    p->index_count = 3 * n;
    p->indices = malloc(sizeof *p->indices * (size_t)(3 * n + 1));
    p->vertex = malloc(sizeof *p->vertex * (size_t)(3 * n + 1));
    p->uv = malloc(sizeof *p->uv * (size_t)(3 * n + 1));
    int32_t *first_uv = malloc(sizeof *first_uv * (size_t)t->vertex_count);
    if (!p->indices || !p->vertex || !p->uv || !first_uv) {
        free(first_uv);
        return fr_nomem(w->ctx, "a glTF primitive");
    }
    for (int v = 0; v < t->vertex_count; v++) first_uv[v] = -1;
    for (int i = 0; i < t->triangle_count; i++) {
        if (t->triangle_materials[i] != material) continue;
        for (int c = 0; c < 3; c++) {
            int32_t v = t->triangles[3 * i + c];
            if (first_uv[v] < 0) first_uv[v] = t->triangle_uvs[3 * i + c];
        }
    }
    for (int v = 0; v < t->vertex_count; v++) {
        if (first_uv[v] < 0) continue;
        int g = p->vertex_count++;
        p->vertex[g] = v;
        p->uv[g] = first_uv[v];
        next[g] = -1;
        head[v] = g;
    }
    p->ict_count = p->vertex_count;
    int k = 0;
    for (int i = 0; i < t->triangle_count; i++) {
        if (t->triangle_materials[i] != material) continue;
        for (int c = 0; c < 3; c++) {
            int32_t v = t->triangles[3 * i + c], uv = t->triangle_uvs[3 * i + c], g = head[v];
            while (g >= 0 && p->uv[g] != uv) g = next[g];
            if (g < 0) { /* a seam copy, chained after the vertex's first */
                g = p->vertex_count++;
                p->vertex[g] = v;
                p->uv[g] = uv;
                next[g] = next[head[v]];
                next[head[v]] = g;
            }
            p->indices[k++] = (uint32_t)g;
        }
    }
    for (int g = 0; g < p->vertex_count; g++) head[p->vertex[g]] = -1;
    free(first_uv);
    return FRIG_OK;
}

static frig_status build_prims(writer *w) {
    const fr_topology *t = &w->rig->topo;
    w->prims = calloc((size_t)t->material_count, sizeof *w->prims);
    int32_t *head = malloc(sizeof *head * (size_t)t->vertex_count);
    int32_t *next = malloc(sizeof *next * (size_t)(3 * t->triangle_count));
    frig_status s = FRIG_OK;
    if (!w->prims || !head || !next) s = fr_nomem(w->ctx, "the glTF primitives");
    for (int v = 0; !s && v < t->vertex_count; v++) head[v] = -1;
    for (int m = 0; !s && m < t->material_count; m++) {
        if (w->look.materials[m].omitted) continue; /* export.eye_overlays 0 */
        prim *p = &w->prims[w->prim_count++];
        s = build_prim(w, m, head, next, p);
        if (!s && p->index_count == 0) { /* an unused material: no primitive */
            free(p->indices), free(p->vertex), free(p->uv);
            memset(p, 0, sizeof *p);
            w->prim_count--;
        }
    }
    free(head);
    free(next);
    return s;
}

static frig_status compute_normals(writer *w) {
    const fr_topology *t = &w->rig->topo;
    size_t n3 = 3 * (size_t)t->vertex_count;
    w->normals = malloc(sizeof(float) * n3);
    w->normal_deltas = malloc(sizeof(float) * n3 * (size_t)(w->shapes.count + 1));
    float *shape = malloc(sizeof(float) * n3);
    frig_status s = FRIG_OK;
    if (!w->normals || !w->normal_deltas || !shape) s = fr_nomem(w->ctx, "normals");
    if (!s) s = fr_vertex_normals(w->ctx, t->vertex_count, w->rig->neutral, t->triangle_count, t->triangles, w->normals);
    for (int k = 0; k < w->shapes.count && !s; k++) {
        const float *d = w->shapes.deltas + n3 * (size_t)k;
        float *nd = w->normal_deltas + n3 * (size_t)k;
        for (size_t i = 0; i < n3; i++) shape[i] = w->rig->neutral[i] + d[i];
        s = fr_vertex_normals(w->ctx, t->vertex_count, shape, t->triangle_count, t->triangles, nd);
        for (size_t i = 0; i < n3; i++) nd[i] -= w->normals[i];
    }
    free(shape);
    return s;
}

static void sep(fr_buffer *b, int count) {
    if (count) fr_buffer_append(b, ",", 1);
}

/* A bufferView over the bytes appended to bin since 'start'. */
static int add_view(writer *w, size_t start, int target) {
    sep(&w->views, w->view_count);
    fr_buffer_printf(&w->views, "{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":%zu", start, w->bin.size - start);
    if (target) fr_buffer_printf(&w->views, ",\"target\":%d", target);
    fr_buffer_append(&w->views, "}", 1);
    fr_buffer_align(&w->bin, 4, 0);
    return w->view_count++;
}

static void write_bounds(fr_buffer *b, const float lo[3], const float hi[3]) {
    fr_buffer_printf(b, ",\"min\":[%.9g,%.9g,%.9g],\"max\":[%.9g,%.9g,%.9g]", lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]);
}

/* Gather vec3 values src[3 * map[i]] for the primitive's vertices, with their bounds. */
static void bounds3(const float *src, const int32_t *map, int n, float lo[3], float hi[3]) {
    for (int d = 0; d < 3; d++) lo[d] = hi[d] = n ? src[3 * map[0] + d] : 0;
    for (int i = 0; i < n; i++)
        for (int d = 0; d < 3; d++) {
            float v = src[3 * map[i] + d];
            lo[d] = v < lo[d] ? v : lo[d];
            hi[d] = v > hi[d] ? v : hi[d];
        }
}

/* A dense VEC3 float accessor of src gathered through the primitive's vertex map. */
static int dense_vec3(writer *w, const prim *p, const float *src, int bounds) {
    size_t start = w->bin.size;
    for (int i = 0; i < p->vertex_count; i++)
        for (int d = 0; d < 3; d++) fr_buffer_f32(&w->bin, src[3 * p->vertex[i] + d]);
    int view = add_view(w, start, GL_ARRAY_BUFFER);
    sep(&w->accessors, w->accessor_count);
    fr_buffer_printf(&w->accessors, "{\"bufferView\":%d,\"componentType\":%d,\"count\":%d,\"type\":\"VEC3\"", view,
                     GL_FLOAT, p->vertex_count);
    if (bounds) {
        float lo[3], hi[3];
        bounds3(src, p->vertex, p->vertex_count, lo, hi);
        write_bounds(&w->accessors, lo, hi);
    }
    fr_buffer_append(&w->accessors, "}", 1);
    return w->accessor_count++;
}

static int moved(const float *v) { return v[0] != 0 || v[1] != 0 || v[2] != 0; }

/* A morph target accessor: all zeros (no data), sparse, or dense, whichever is smallest. */
static int zero_vec3(writer *w, const prim *p);

static int target_vec3(writer *w, const prim *p, const float *src, int *zero_accessor) {
    int nnz = 0;
    for (int i = 0; i < p->vertex_count; i++) nnz += moved(src + 3 * p->vertex[i]);
    if (nnz == 0) {
        if (*zero_accessor < 0) *zero_accessor = zero_vec3(w, p); /* shared by every still target */
        return *zero_accessor;
    }
    int wide = p->vertex_count > 65535;
    size_t isize = wide ? 4 : 2;
    if ((size_t)nnz * (isize + 12) >= (size_t)p->vertex_count * 12) return dense_vec3(w, p, src, 1);
    float lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
    size_t start = w->bin.size;
    for (int i = 0; i < p->vertex_count; i++) {
        if (!moved(src + 3 * p->vertex[i])) continue;
        if (wide) fr_buffer_u32(&w->bin, (uint32_t)i);
        else fr_buffer_u16(&w->bin, (uint16_t)i);
    }
    int iview = add_view(w, start, 0);
    start = w->bin.size;
    for (int i = 0; i < p->vertex_count; i++) {
        const float *v = src + 3 * p->vertex[i];
        if (!moved(v)) continue;
        for (int d = 0; d < 3; d++) {
            fr_buffer_f32(&w->bin, v[d]);
            lo[d] = v[d] < lo[d] ? v[d] : lo[d];
            hi[d] = v[d] > hi[d] ? v[d] : hi[d];
        }
    }
    int vview = add_view(w, start, 0);
    sep(&w->accessors, w->accessor_count);
    fr_buffer_printf(&w->accessors, "{\"componentType\":%d,\"count\":%d,\"type\":\"VEC3\"", GL_FLOAT, p->vertex_count);
    write_bounds(&w->accessors, lo, hi);
    fr_buffer_printf(&w->accessors,
                     ",\"sparse\":{\"count\":%d,\"indices\":{\"bufferView\":%d,\"componentType\":%d},"
                     "\"values\":{\"bufferView\":%d}}}",
                     nnz, iview, wide ? GL_UNSIGNED_INT : GL_UNSIGNED_SHORT, vview);
    return w->accessor_count++;
}

static int zero_vec3(writer *w, const prim *p) {
    sep(&w->accessors, w->accessor_count);
    fr_buffer_printf(&w->accessors, "{\"componentType\":%d,\"count\":%d,\"type\":\"VEC3\"", GL_FLOAT, p->vertex_count);
    float z[3] = {0, 0, 0};
    write_bounds(&w->accessors, z, z);
    fr_buffer_append(&w->accessors, "}", 1);
    return w->accessor_count++;
}

static int texcoords(writer *w, const prim *p) {
    size_t start = w->bin.size;
    const float *uv = w->rig->topo.uvs;
    for (int i = 0; i < p->vertex_count; i++) {
        fr_buffer_f32(&w->bin, uv[2 * p->uv[i]]);
        fr_buffer_f32(&w->bin, 1.0f - uv[2 * p->uv[i] + 1]); /* glTF's v runs down the image */
    }
    int view = add_view(w, start, GL_ARRAY_BUFFER);
    sep(&w->accessors, w->accessor_count);
    fr_buffer_printf(&w->accessors, "{\"bufferView\":%d,\"componentType\":%d,\"count\":%d,\"type\":\"VEC2\"}", view,
                     GL_FLOAT, p->vertex_count);
    return w->accessor_count++;
}

static int indices(writer *w, const prim *p) {
    int wide = p->vertex_count > 65535;
    size_t start = w->bin.size;
    uint32_t lo = UINT32_MAX, hi = 0;
    for (int i = 0; i < p->index_count; i++) {
        uint32_t v = p->indices[i];
        lo = v < lo ? v : lo;
        hi = v > hi ? v : hi;
        if (wide) fr_buffer_u32(&w->bin, v);
        else fr_buffer_u16(&w->bin, (uint16_t)v);
    }
    int view = add_view(w, start, GL_ELEMENT_ARRAY_BUFFER);
    sep(&w->accessors, w->accessor_count);
    fr_buffer_printf(&w->accessors, "{\"bufferView\":%d,\"componentType\":%d,\"count\":%d,\"type\":\"SCALAR\"}", view,
                     wide ? GL_UNSIGNED_INT : GL_UNSIGNED_SHORT, p->index_count);
    return w->accessor_count++;
}

/* The primitive's accessors, and its JSON object into 'json'. */
static void write_prim(writer *w, const prim *p, int material_slot, fr_buffer *json) {
    size_t n3 = 3 * (size_t)w->rig->topo.vertex_count;
    int pos = dense_vec3(w, p, w->rig->neutral, 1);
    int nrm = dense_vec3(w, p, w->normals, 0);
    int tex = texcoords(w, p);
    int idx = indices(w, p);
    int zero = -1;
    fr_buffer_printf(json,
                     "{\"attributes\":{\"POSITION\":%d,\"NORMAL\":%d,\"TEXCOORD_0\":%d},\"indices\":%d,"
                     "\"material\":%d,\"mode\":4,\"targets\":[",
                     pos, nrm, tex, idx, material_slot);
    for (int k = 0; k < w->shapes.count; k++) {
        int tp = target_vec3(w, p, w->shapes.deltas + n3 * (size_t)k, &zero);
        int tn = target_vec3(w, p, w->normal_deltas + n3 * (size_t)k, &zero);
        fr_buffer_printf(json, "%s{\"POSITION\":%d,\"NORMAL\":%d}", k ? "," : "", tp, tn);
    }
    /* which ICT vertex each glTF vertex is; the first ictVertexCount are ICT's, in order */
    fr_buffer_printf(json, "],\"extras\":{\"ictVertexCount\":%d,\"ictVertexIndex\":[", p->ict_count);
    for (int i = 0; i < p->vertex_count; i++) fr_buffer_printf(json, "%s%d", i ? "," : "", p->vertex[i]);
    fr_buffer_append(json, "]}}", 3);
}

static const char *const alpha_modes[3] = {"OPAQUE", "MASK", "BLEND"};

static void write_materials(writer *w, fr_buffer *json) {
    const fr_topology *t = &w->rig->topo;
    fr_buffer_append(json, "\"materials\":[", 13);
    for (int i = 0; i < w->prim_count; i++) {
        const fr_material_look *l = &w->look.materials[w->prims[i].material];
        fr_buffer_printf(json, "%s{\"name\":\"%s\",\"pbrMetallicRoughness\":{\"baseColorFactor\":[%.6g,%.6g,%.6g,%.6g]",
                         i ? "," : "", t->material_names[w->prims[i].material], l->base[0], l->base[1], l->base[2],
                         l->base[3]);
        if (l->texture >= 0) fr_buffer_printf(json, ",\"baseColorTexture\":{\"index\":%d}", l->texture);
        fr_buffer_printf(json, ",\"metallicFactor\":0,\"roughnessFactor\":%.6g}", l->roughness);
        if (l->alpha_mode != FR_ALPHA_OPAQUE) fr_buffer_printf(json, ",\"alphaMode\":\"%s\"", alpha_modes[l->alpha_mode]);
        if (l->alpha_mode == FR_ALPHA_MASK) fr_buffer_append(json, ",\"alphaCutoff\":0.5", 18);
        if (l->double_sided) fr_buffer_append(json, ",\"doubleSided\":true", 19);
        fr_buffer_append(json, "}", 1);
    }
    fr_buffer_append(json, "]", 1);
}

/* The look's textures: PNG bytes in the binary chunk, one image, one texture each, a shared
 * sampler (linear, mipmapped, clamped: each UV island has its gutter). */
static void write_textures(writer *w, fr_buffer *json) {
    if (!w->look.texture_count) return;
    fr_buffer images = {0};
    for (int i = 0; i < w->look.texture_count; i++) {
        const fr_texture *tex = &w->look.textures[i];
        size_t start = w->bin.size;
        fr_buffer_append(&w->bin, tex->png, tex->png_size);
        int view = add_view(w, start, 0);
        fr_buffer_printf(&images, "%s{\"name\":\"%.*s\",\"bufferView\":%d,\"mimeType\":\"image/png\"}", i ? "," : "",
                         (int)(strlen(tex->file) - 4), tex->file, view);
    }
    fr_buffer_append(json, ",\"images\":[", 11);
    fr_buffer_append(json, images.data, images.size);
    fr_buffer_append(json, "],\"samplers\":[{\"magFilter\":9729,\"minFilter\":9987,\"wrapS\":33071,\"wrapT\":33071}]", 78);
    fr_buffer_append(json, ",\"textures\":[", 13);
    for (int i = 0; i < w->look.texture_count; i++) fr_buffer_printf(json, "%s{\"sampler\":0,\"source\":%d}", i ? "," : "", i);
    fr_buffer_append(json, "]", 1);
    if (images.failed) w->bin.failed = 1;
    fr_buffer_free(&images);
}

static void write_json(writer *w, fr_buffer *json) {
    fr_buffer prims = {0};
    for (int i = 0; i < w->prim_count; i++) {
        sep(&prims, i);
        write_prim(w, &w->prims[i], i, &prims);
    }
    fr_buffer_printf(json,
                     "{\"asset\":{\"version\":\"2.0\",\"generator\":\"libfrig %s\"},\"scene\":0,"
                     "\"scenes\":[{\"nodes\":[0]}],\"nodes\":[{\"name\":\"head\",\"mesh\":0}],"
                     "\"meshes\":[{\"name\":\"head\",\"primitives\":[",
                     frig_version_string());
    fr_buffer_append(json, prims.data, prims.size);
    fr_buffer_append(json, "],\"weights\":[", 13);
    for (int k = 0; k < w->shapes.count; k++) fr_buffer_printf(json, "%s0", k ? "," : "");
    fr_buffer_append(json, "],\"extras\":{\"targetNames\":[", 27);
    for (int k = 0; k < w->shapes.count; k++) fr_buffer_printf(json, "%s\"%s\"", k ? "," : "", w->shapes.names[k]);
    fr_buffer_append(json, "]}}],", 5);
    write_materials(w, json);
    write_textures(w, json);
    fr_buffer_append(json, ",\"accessors\":[", 14);
    fr_buffer_append(json, w->accessors.data, w->accessors.size);
    fr_buffer_append(json, "],\"bufferViews\":[", 17);
    fr_buffer_append(json, w->views.data, w->views.size);
    fr_buffer_printf(json, "],\"buffers\":[{\"byteLength\":%zu}]}", w->bin.size);
    fr_buffer_free(&prims);
}

/* GLB: 12-byte header, the JSON chunk padded with spaces, the BIN chunk padded with zeros. */
static frig_status write_glb(writer *w, fr_buffer *json, const char *path) {
    fr_buffer_align(json, 4, ' ');
    fr_buffer_align(&w->bin, 4, 0);
    fr_buffer glb = {0};
    fr_buffer_u32(&glb, 0x46546C67u); /* "glTF" */
    fr_buffer_u32(&glb, 2);
    fr_buffer_u32(&glb, (uint32_t)(12 + 8 + json->size + 8 + w->bin.size));
    fr_buffer_u32(&glb, (uint32_t)json->size);
    fr_buffer_u32(&glb, 0x4E4F534Au); /* "JSON" */
    fr_buffer_append(&glb, json->data, json->size);
    fr_buffer_u32(&glb, (uint32_t)w->bin.size);
    fr_buffer_u32(&glb, 0x004E4942u); /* "BIN\0" */
    fr_buffer_append(&glb, w->bin.data, w->bin.size);
    frig_status s = glb.failed || json->failed || w->bin.failed || w->accessors.failed || w->views.failed
                        ? fr_nomem(w->ctx, "the glTF file")
                        : fr_write_file_atomic(w->ctx, path, glb.data, glb.size);
    fr_buffer_free(&glb);
    return s;
}

frig_status frig_rig_save_gltf(frig_ctx *ctx, const frig_rig *rig, const char *path) {
    if (!rig || !path) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_rig_save_gltf: NULL rig or path");
    writer w;
    memset(&w, 0, sizeof w);
    w.ctx = ctx;
    w.rig = rig;
    fr_buffer json = {0};
    frig_status s;
    if (!(s = fr_rig_look_make(ctx, rig, &w.look)) && !(s = fr_export_shapes_make(ctx, rig, &w.shapes)) &&
        !(s = compute_normals(&w)) && !(s = build_prims(&w))) {
        write_json(&w, &json);
        s = write_glb(&w, &json, path);
    }
    fr_buffer_free(&json);
    fr_buffer_free(&w.bin);
    fr_buffer_free(&w.accessors);
    fr_buffer_free(&w.views);
    prims_free(&w);
    free(w.normals);
    free(w.normal_deltas);
    fr_export_shapes_free(&w.shapes);
    fr_rig_look_free(&w.look);
    return s;
}
