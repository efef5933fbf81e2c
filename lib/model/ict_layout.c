/* ICT-FaceKit's topology as its README (README.upstream.md, "Face Model Topology", "Face
 * Area Details", "Eyeball Details", "Facial Landmarks") gives it, checked against the mesh
 * before it is trusted. */
#include <stdlib.h>

#include "core/context.h"
#include "model/ict_layout.h"

static const fr_ict_region regions[] = {
    {"face", 0, 9408, 0, 9229, 1},
    {"narrow_face", 0, 6705, 0, 6559, 0},
    {"head_neck", 9409, 11247, 9230, 11143, 1},
    {"mouth_socket", 11248, 13293, 11144, 13225, 1},
    {"eye_socket_left", 13294, 13677, 13226, 13629, 1},
    {"eye_socket_right", 13678, 14061, 13630, 14033, 1},
    {"gums_tongue", 14062, 17038, 14034, 17005, 1},
    {"teeth", 17039, 21450, 17006, 21495, 1},
    {"eyeball_left", 21451, 23020, 21496, 23093, 1},
    {"eyeball_right", 23021, 24590, 23094, 24691, 1},
    {"lacrimal_fluid_left", 24591, 24794, 24692, 24854, 1},
    {"lacrimal_fluid_right", 24795, 24998, 24855, 25017, 1},
    {"eye_blend_left", 24999, 25022, 25018, 25032, 1},
    {"eye_blend_right", 25023, 25046, 25033, 25047, 1},
    {"eye_occlusion_left", 25047, 25198, 25048, 25175, 1},
    {"eye_occlusion_right", 25199, 25350, 25176, 25303, 1},
    {"eyelashes_left", 25351, 26034, 25304, 25843, 1},
    {"eyelashes_right", 26035, 26718, 25844, 26383, 1},
    {"sclera_left", 21451, 22220, 21496, 22295, 0},
    {"iris_left", 22221, 23020, 22296, 23093, 0},
    {"sclera_right", 23021, 23790, 23094, 23893, 0},
    {"iris_right", 23791, 24590, 23894, 24691, 0},
};

/* README order is ear -> chin for the right list and chin -> ear for the left one; the
 * left list is stored reversed so both run from the ear toward the chin. */
static const int32_t contour_right[] = {1280, 1278, 1275, 1272, 1248, 12,  820,  1834, 1902,
                                        243,  844,  781,  1673, 2199, 801, 1447, 800};
static const int32_t contour_left[] = {3498, 3496, 3493, 3490, 3466, 2253, 3061, 4036, 4102,
                                       2484, 3085, 3022, 3880, 4390, 3042, 3661, 3041};

int fr_ict_region_count(void) { return (int)(sizeof regions / sizeof regions[0]); }
const fr_ict_region *fr_ict_region_at(int i) { return &regions[i]; }

int fr_ict_contour(int side, const int32_t **vertices) {
    *vertices = side == 0 ? contour_right : contour_left;
    return side == 0 ? (int)(sizeof contour_right / sizeof contour_right[0])
                     : (int)(sizeof contour_left / sizeof contour_left[0]);
}

/* The part's polygons reference only vertices up to its last one, and all of its own. */
static frig_status check_region(frig_ctx *ctx, const char *file, const fr_obj *o, const fr_ict_region *r,
                                unsigned char *seen) {
    int nv = r->last_vertex - r->first_vertex + 1;
    for (int i = 0; i < nv; i++) seen[i] = 0;
    for (int p = r->first_polygon; p <= r->last_polygon; p++)
        for (int c = o->offsets[p]; c < o->offsets[p + 1]; c++) {
            int v = o->corners[c];
            if (v > r->last_vertex)
                return fr_error(ctx, FRIG_ERR_UNSUPPORTED,
                                "%s: polygon %d of '%s' uses vertex %d, past the part's last vertex %d: the mesh "
                                "does not follow ICT-FaceKit's documented layout",
                                file, p, r->name, v, r->last_vertex);
            if (v >= r->first_vertex) seen[v - r->first_vertex] = 1;
        }
    for (int i = 0; i < nv; i++)
        if (!seen[i])
            return fr_error(ctx, FRIG_ERR_UNSUPPORTED,
                            "%s: vertex %d of '%s' is used by none of its polygons %d..%d: the mesh does not follow "
                            "ICT-FaceKit's documented layout",
                            file, r->first_vertex + i, r->name, r->first_polygon, r->last_polygon);
    return FRIG_OK;
}

frig_status fr_ict_check_layout(frig_ctx *ctx, const char *file, const fr_obj *o) {
    if (o->vertex_count != FR_ICT_VERTEX_COUNT || o->polygon_count != FR_ICT_POLYGON_COUNT)
        return fr_error(ctx, FRIG_ERR_UNSUPPORTED,
                        "%s: %d vertices and %d polygons; the ICT-FaceKit layout this importer knows has %d and %d",
                        file, o->vertex_count, o->polygon_count, FR_ICT_VERTEX_COUNT, FR_ICT_POLYGON_COUNT);
    int next_v = 0, next_p = 0;
    for (int i = 0; i < fr_ict_region_count(); i++) {
        const fr_ict_region *r = &regions[i];
        if (!r->partition) continue;
        if (r->first_vertex != next_v || r->first_polygon != next_p)
            return fr_error(ctx, FRIG_ERR_INTERNAL, "ICT layout table: '%s' does not follow the previous part", r->name);
        next_v = r->last_vertex + 1;
        next_p = r->last_polygon + 1;
    }
    if (next_v != FR_ICT_VERTEX_COUNT || next_p != FR_ICT_POLYGON_COUNT)
        return fr_error(ctx, FRIG_ERR_INTERNAL, "ICT layout table does not cover the mesh");
    unsigned char *seen = malloc(FR_ICT_VERTEX_COUNT);
    if (!seen) return fr_nomem(ctx, "the layout check");
    frig_status s = FRIG_OK;
    for (int i = 0; i < fr_ict_region_count() && !s; i++) s = check_region(ctx, file, o, &regions[i], seen);
    free(seen);
    for (int side = 0; side < 2 && !s; side++) {
        const int32_t *v;
        int n = fr_ict_contour(side, &v);
        for (int i = 0; i < n; i++)
            if (v[i] >= regions[0].last_vertex + 1)
                s = fr_error(ctx, FRIG_ERR_INTERNAL, "ICT jawline vertex %d is not on the face", v[i]);
    }
    return s;
}
