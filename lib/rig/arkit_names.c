/* Apple ARKit's 52 blendshape names (ARFaceAnchor.BlendShapeLocation, in Apple's order) and
 * the mapping from ICT-FaceKit's spellings: "_L"/"_R" become "Left"/"Right", and ICT's split
 * halves of a shape ARKit keeps whole (browInnerUp_L/_R, cheekPuff_L/_R) share its name. */
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "rig/rig.h"

static const char *const arkit[] = {
    "eyeBlinkLeft",     "eyeLookDownLeft",   "eyeLookInLeft",      "eyeLookOutLeft",      "eyeLookUpLeft",
    "eyeSquintLeft",    "eyeWideLeft",       "eyeBlinkRight",      "eyeLookDownRight",    "eyeLookInRight",
    "eyeLookOutRight",  "eyeLookUpRight",    "eyeSquintRight",     "eyeWideRight",        "jawForward",
    "jawLeft",          "jawRight",          "jawOpen",            "mouthClose",          "mouthFunnel",
    "mouthPucker",      "mouthLeft",         "mouthRight",         "mouthSmileLeft",      "mouthSmileRight",
    "mouthFrownLeft",   "mouthFrownRight",   "mouthDimpleLeft",    "mouthDimpleRight",    "mouthStretchLeft",
    "mouthStretchRight", "mouthRollLower",   "mouthRollUpper",     "mouthShrugLower",     "mouthShrugUpper",
    "mouthPressLeft",   "mouthPressRight",   "mouthLowerDownLeft", "mouthLowerDownRight", "mouthUpperUpLeft",
    "mouthUpperUpRight", "browDownLeft",     "browDownRight",      "browInnerUp",         "browOuterUpLeft",
    "browOuterUpRight", "cheekPuff",         "cheekSquintLeft",    "cheekSquintRight",    "noseSneerLeft",
    "noseSneerRight",   "tongueOut",
};
#define ARKIT_COUNT ((int)(sizeof arkit / sizeof arkit[0]))

int frig_arkit_name_count(void) { return ARKIT_COUNT; }
const char *frig_arkit_name(int i) { return i >= 0 && i < ARKIT_COUNT ? arkit[i] : NULL; }

static int arkit_index_n(const char *name, size_t n) {
    for (int i = 0; i < ARKIT_COUNT; i++)
        if (strlen(arkit[i]) == n && memcmp(arkit[i], name, n) == 0) return i;
    return -1;
}

/* ARKit index of an ICT-style name, or -1 when ARKit has no such shape. */
static int arkit_index_of(const char *name) {
    size_t n = strlen(name);
    int i = arkit_index_n(name, n);
    if (i >= 0 || n < 3 || n > 60 || name[n - 2] != '_' || (name[n - 1] != 'L' && name[n - 1] != 'R')) return i;
    char buf[72];
    memcpy(buf, name, n - 2);
    strcpy(buf + n - 2, name[n - 1] == 'L' ? "Left" : "Right");
    i = arkit_index_n(buf, strlen(buf));
    return i >= 0 ? i : arkit_index_n(name, n - 2); /* a split half of a whole ARKit shape */
}

const char *frig_rig_arkit_name(const frig_rig *rig, int k) {
    const char *own = frig_rig_shape_name(rig, k);
    if (!own) return NULL;
    int i = arkit_index_of(own);
    return i >= 0 ? arkit[i] : own;
}

int frig_rig_provides_arkit(const frig_rig *rig, const char *arkit_name) {
    if (!rig || !arkit_name) return 0;
    for (int k = 0; k < rig->shape_count; k++)
        if (strcmp(frig_rig_arkit_name(rig, k), arkit_name) == 0) return 1;
    return 0;
}

/* The exported names in order: ARKit's order first, then the shapes ARKit lacks in rig order.
 * names has room for shape_count entries. */
static int target_names(const frig_rig *rig, const char **names) {
    int n = 0;
    for (int i = 0; i < ARKIT_COUNT; i++)
        if (frig_rig_provides_arkit(rig, arkit[i])) names[n++] = arkit[i];
    for (int k = 0; k < rig->shape_count; k++)
        if (arkit_index_of(rig->shape_names[k]) < 0) names[n++] = rig->shape_names[k];
    return n;
}

int frig_rig_target_count(const frig_rig *rig) {
    if (!rig) return 0;
    int n = 0;
    for (int i = 0; i < ARKIT_COUNT; i++) n += frig_rig_provides_arkit(rig, arkit[i]);
    for (int k = 0; k < rig->shape_count; k++) n += arkit_index_of(rig->shape_names[k]) < 0;
    return n;
}

const char *frig_rig_target_name(const frig_rig *rig, int i) {
    if (!rig || i < 0) return NULL;
    for (int a = 0; a < ARKIT_COUNT; a++)
        if (frig_rig_provides_arkit(rig, arkit[a]) && i-- == 0) return arkit[a];
    for (int k = 0; k < rig->shape_count; k++)
        if (arkit_index_of(rig->shape_names[k]) < 0 && i-- == 0) return rig->shape_names[k];
    return NULL;
}

frig_status fr_export_shapes_make(frig_ctx *ctx, const frig_rig *rig, fr_export_shapes *out) {
    memset(out, 0, sizeof *out);
    size_t n3 = 3 * (size_t)rig->topo.vertex_count;
    int cap = rig->shape_count;
    out->names = malloc(sizeof *out->names * (size_t)(cap + 1));
    out->deltas = malloc(sizeof *out->deltas * n3 * (size_t)(cap + 1));
    if (!out->names || !out->deltas) {
        fr_export_shapes_free(out);
        return fr_nomem(ctx, "the exported shapes");
    }
    out->count = target_names(rig, out->names);
    /* Each target sums the rig shapes that carry its name (ICT's split halves). */
    for (int t = 0; t < out->count; t++) {
        float *dst = out->deltas + n3 * (size_t)t;
        memset(dst, 0, n3 * sizeof *dst);
        for (int k = 0; k < rig->shape_count; k++) {
            if (strcmp(frig_rig_arkit_name(rig, k), out->names[t]) != 0) continue;
            const float *src = rig->deltas + n3 * (size_t)k;
            for (size_t i = 0; i < n3; i++) dst[i] += src[i];
        }
    }
    return FRIG_OK;
}

void fr_export_shapes_free(fr_export_shapes *s) {
    free((void *)s->names);
    free(s->deltas);
    memset(s, 0, sizeof *s);
}
