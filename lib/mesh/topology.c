/* Storing and validating mesh topology in the model and rig files: every index is checked
 * against its count so that a hostile file gives a status, never an out-of-bounds read. */
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "mesh/topology.h"

void fr_topology_sections(const fr_topology *t, int32_t meta[FR_TOPOLOGY_META], fr_section *s) {
    meta[0] = t->vertex_count;
    meta[1] = t->polygon_count;
    meta[2] = t->corner_count;
    meta[3] = t->triangle_count;
    meta[4] = t->uv_count;
    meta[5] = t->material_count;
    meta[6] = t->region_count;
    int i = 0;
    s[i++] = (fr_section){"topo_meta", FR_SEC_I32, FR_TOPOLOGY_META, meta};
    s[i++] = (fr_section){"poly_offsets", FR_SEC_I32, (uint64_t)t->polygon_count + 1, t->poly_offsets};
    s[i++] = (fr_section){"poly_corners", FR_SEC_I32, (uint64_t)t->corner_count, t->poly_corners};
    s[i++] = (fr_section){"poly_uvs", FR_SEC_I32, (uint64_t)t->corner_count, t->poly_uvs};
    s[i++] = (fr_section){"poly_materials", FR_SEC_I32, (uint64_t)t->polygon_count, t->poly_materials};
    s[i++] = (fr_section){"triangles", FR_SEC_I32, 3 * (uint64_t)t->triangle_count, t->triangles};
    s[i++] = (fr_section){"triangle_uvs", FR_SEC_I32, 3 * (uint64_t)t->triangle_count, t->triangle_uvs};
    s[i++] = (fr_section){"tri_materials", FR_SEC_I32, (uint64_t)t->triangle_count, t->triangle_materials};
    s[i++] = (fr_section){"uvs", FR_SEC_F32, 2 * (uint64_t)t->uv_count, t->uvs};
    s[i++] = (fr_section){"material_names", FR_SEC_BYTES, t->material_blob_size, t->material_blob};
    s[i++] = (fr_section){"material_kd", FR_SEC_F32, 3 * (uint64_t)t->material_count, t->material_kd};
    s[i++] = (fr_section){"region_names", FR_SEC_BYTES, t->region_blob_size, t->region_blob};
    s[i++] = (fr_section){"regions", FR_SEC_I32, 2 * (uint64_t)t->region_count, t->regions};
}

/* First index outside [0, limit), or -1 when all are inside. */
static int64_t out_of_range(const int32_t *v, uint64_t n, int32_t limit) {
    for (uint64_t i = 0; i < n; i++)
        if (v[i] < 0 || v[i] >= limit) return (int64_t)i;
    return -1;
}

static frig_status check_indices(frig_ctx *ctx, const fr_container *c, const char *tag, const int32_t *v, uint64_t n,
                                 int32_t limit, const char *what) {
    int64_t bad = out_of_range(v, n, limit);
    if (bad < 0) return FRIG_OK;
    return fr_error(ctx, FRIG_ERR_CORRUPT, "%s: '%s' value %lld is %d, outside the %d %s", c->what, tag,
                    (long long)bad, v[bad], limit, what);
}

static frig_status take_counts(frig_ctx *ctx, const fr_container *c, fr_topology *t) {
    void *p;
    frig_status s = fr_container_take(ctx, c, "topo_meta", FR_SEC_I32, FR_TOPOLOGY_META, &p);
    if (s) return s;
    const int32_t *m = p;
    for (int i = 0; i < FR_TOPOLOGY_META; i++)
        if (m[i] < 0 || m[i] > (1 << 28))
            return fr_error(ctx, FRIG_ERR_CORRUPT, "%s: topology count %d is %d", c->what, i, m[i]);
    if (m[0] < 1 || m[3] < 1 || m[5] < 1)
        return fr_error(ctx, FRIG_ERR_CORRUPT, "%s: a mesh needs vertices, triangles and a material", c->what);
    t->vertex_count = m[0], t->polygon_count = m[1], t->corner_count = m[2], t->triangle_count = m[3];
    t->uv_count = m[4], t->material_count = m[5], t->region_count = m[6];
    return FRIG_OK;
}

static frig_status take_arrays(frig_ctx *ctx, const fr_container *c, fr_topology *t) {
    const fr_section_want want[] = {
        {"poly_offsets", FR_SEC_I32, (uint64_t)t->polygon_count + 1, (const void **)&t->poly_offsets},
        {"poly_corners", FR_SEC_I32, (uint64_t)t->corner_count, (const void **)&t->poly_corners},
        {"poly_uvs", FR_SEC_I32, (uint64_t)t->corner_count, (const void **)&t->poly_uvs},
        {"poly_materials", FR_SEC_I32, (uint64_t)t->polygon_count, (const void **)&t->poly_materials},
        {"triangles", FR_SEC_I32, 3 * (uint64_t)t->triangle_count, (const void **)&t->triangles},
        {"triangle_uvs", FR_SEC_I32, 3 * (uint64_t)t->triangle_count, (const void **)&t->triangle_uvs},
        {"tri_materials", FR_SEC_I32, (uint64_t)t->triangle_count, (const void **)&t->triangle_materials},
        {"uvs", FR_SEC_F32, 2 * (uint64_t)t->uv_count, (const void **)&t->uvs},
        {"material_kd", FR_SEC_F32, 3 * (uint64_t)t->material_count, (const void **)&t->material_kd},
        {"regions", FR_SEC_I32, 2 * (uint64_t)t->region_count, (const void **)&t->regions},
    };
    return fr_container_take_all(ctx, c, want, (int)(sizeof want / sizeof want[0]));
}

static frig_status check_polygons(frig_ctx *ctx, const fr_container *c, const fr_topology *t) {
    const int32_t *o = t->poly_offsets;
    if (o[0] != 0 || o[t->polygon_count] != t->corner_count)
        return fr_error(ctx, FRIG_ERR_CORRUPT, "%s: polygon offsets do not span the %d corners", c->what,
                        t->corner_count);
    for (int p = 0; p < t->polygon_count; p++)
        if (o[p + 1] - o[p] < 3 || o[p + 1] > t->corner_count)
            return fr_error(ctx, FRIG_ERR_CORRUPT, "%s: polygon %d has offsets %d..%d", c->what, p, o[p], o[p + 1]);
    frig_status s;
    if ((s = check_indices(ctx, c, "poly_corners", t->poly_corners, (uint64_t)t->corner_count, t->vertex_count,
                           "vertices")) ||
        (s = check_indices(ctx, c, "poly_uvs", t->poly_uvs, (uint64_t)t->corner_count, t->uv_count, "uvs")) ||
        (s = check_indices(ctx, c, "poly_materials", t->poly_materials, (uint64_t)t->polygon_count,
                           t->material_count, "materials")) ||
        (s = check_indices(ctx, c, "triangles", t->triangles, 3 * (uint64_t)t->triangle_count, t->vertex_count,
                           "vertices")) ||
        (s = check_indices(ctx, c, "triangle_uvs", t->triangle_uvs, 3 * (uint64_t)t->triangle_count, t->uv_count,
                           "uvs")) ||
        (s = check_indices(ctx, c, "tri_materials", t->triangle_materials, (uint64_t)t->triangle_count,
                           t->material_count, "materials")))
        return s;
    return FRIG_OK;
}

static frig_status check_regions(frig_ctx *ctx, const fr_container *c, const fr_topology *t) {
    for (int r = 0; r < t->region_count; r++) {
        int32_t first = t->regions[2 * r], n = t->regions[2 * r + 1];
        if (first < 0 || n < 0 || first > t->vertex_count - n)
            return fr_error(ctx, FRIG_ERR_CORRUPT, "%s: region '%s' (%d vertices from %d) is outside the %d vertices",
                            c->what, t->region_names[r], n, first, t->vertex_count);
    }
    if (!fr_all_finite(t->uvs, 2 * (uint64_t)t->uv_count) ||
        !fr_all_finite(t->material_kd, 3 * (uint64_t)t->material_count))
        return fr_error(ctx, FRIG_ERR_CORRUPT, "%s: UVs or material colours are not finite numbers", c->what);
    return FRIG_OK;
}

frig_status fr_topology_bind(frig_ctx *ctx, const fr_container *c, fr_topology *t) {
    memset(t, 0, sizeof *t);
    frig_status s;
    if ((s = take_counts(ctx, c, t)) || (s = take_arrays(ctx, c, t)) ||
        (s = fr_names_parse(ctx, c, "material_names", t->material_count, &t->material_names, &t->material_blob,
                            &t->material_blob_size)) ||
        (s = fr_names_parse(ctx, c, "region_names", t->region_count, &t->region_names, &t->region_blob,
                            &t->region_blob_size)) ||
        (s = check_polygons(ctx, c, t)) || (s = check_regions(ctx, c, t))) {
        fr_topology_release(t);
        return s;
    }
    return FRIG_OK;
}

void fr_topology_release(fr_topology *t) {
    free((void *)t->material_names);
    free((void *)t->region_names);
    t->material_names = t->region_names = NULL;
}

int fr_topology_region(const fr_topology *t, const char *name, int *first, int *count) {
    for (int r = 0; r < t->region_count; r++)
        if (strcmp(t->region_names[r], name) == 0) {
            *first = t->regions[2 * r];
            *count = t->regions[2 * r + 1];
            return *count > 0;
        }
    return 0;
}

int fr_topology_material(const fr_topology *t, const char *name) {
    for (int m = 0; m < t->material_count; m++)
        if (strcmp(t->material_names[m], name) == 0) return m;
    return -1;
}

static const char *triangle_material(const fr_topology *t, int i) {
    int m = t->triangle_materials[i];
    return m >= 0 && m < t->material_count ? t->material_names[m] : NULL;
}

int fr_topology_opaque(const fr_topology *t, int i) {
    static const char *const overlays[] = {"M_LacrimalFluid", "M_EyeBlend", "M_EyeOcclusion", "M_EyeLashes"};
    const char *name = triangle_material(t, i);
    for (size_t k = 0; k < sizeof overlays / sizeof overlays[0]; k++)
        if (name && strcmp(name, overlays[k]) == 0) return 0;
    return 1;
}

int fr_topology_face_skin(const fr_topology *t, int i) {
    const char *name = triangle_material(t, i);
    return name && strcmp(name, "M_Face") == 0;
}
