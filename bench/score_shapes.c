/* The held-out check's scorer, as the issue states it: an exported rig's shapes/ OBJ files (frig
 * export) scored per vertex against a synthetic subject's true rig, exported the same way
 * (ARKit-named targets, split shapes summed):
 *   neutral mean: mean distance per vertex of neutral.obj to the true neutral, over the face
 *     region (vertices 0-9408) and over the whole head; raw (the rig's frame) and after the
 *     best similarity transform;
 *   delta error over moving vertices: the mean |d - d_true| (d = target.obj - neutral.obj) over
 *     every (target, vertex) the true delta moves by more than 0.1 mm (as bench/rig_error.c).
 * Usage: score_shapes SHAPES_DIR TRUTH_RIG [TEMPLATE_MODEL]
 * With TEMPLATE_MODEL, also the bar: the best in-span neutral (needs subject.json beside the
 * rig's folder) carrying the template's deltas. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "eval/shape_error.h"
#include "frig/frig.h"
#include "model/obj_reader.h"
#include "rig/rig.h"
#include "synth_truth.h"

#define FACE 9409
#define MOVING 1e-4

static float *read_obj(const char *path, int nv) {
    char *text = synth_read_text(path);
    if (!text) return NULL;
    fr_obj obj;
    char err[256];
    float *x = NULL;
    if (fr_obj_parse(text, strlen(text), path, &obj, err, sizeof err) == FRIG_OK) {
        if (obj.vertex_count == nv && (x = malloc(sizeof(float) * 3 * nv)))
            for (int k = 0; k < 3 * nv; k++) x[k] = (float)obj.positions[k];
        fr_obj_free(&obj);
    } else {
        fprintf(stderr, "%s\n", err);
    }
    free(text);
    return x;
}

static double mean_dist(const float *a, const float *b, int from, int to) {
    double s = 0;
    for (int v = from; v < to; v++) {
        double d = 0;
        for (int k = 0; k < 3; k++) d += (a[3 * v + k] - b[3 * v + k]) * (a[3 * v + k] - b[3 * v + k]);
        s += sqrt(d);
    }
    return s / (to - from);
}

typedef struct score {
    double face_raw, face_aligned, head_raw, delta_face, delta_head;
    int targets;
} score;

/* Score positions (neutral and one full shape per target, the truth's target order) against
 * the truth's export shapes. */
static score score_shapes(const frig_rig *truth, const fr_export_shapes *tx, const float *neutral,
                          float *const *shapes) {
    int nv = frig_rig_vertex_count(truth);
    const float *tn = frig_rig_neutral(truth);
    score s = {mean_dist(neutral, tn, 0, FACE), fr_aligned_mean_distance(tn, neutral, FACE), mean_dist(neutral, tn, 0, nv),
               0, 0, 0};
    double ef = 0, eh = 0;
    long nf = 0, nh = 0;
    for (int i = 0; i < tx->count; i++) {
        if (!shapes[i]) continue;
        const float *td = tx->deltas + 3 * (size_t)nv * i;
        for (int v = 0; v < nv; v++) {
            double m = 0, e = 0;
            for (int k = 0; k < 3; k++) {
                double d = shapes[i][3 * v + k] - neutral[3 * v + k];
                m += td[3 * v + k] * td[3 * v + k];
                e += (d - td[3 * v + k]) * (d - td[3 * v + k]);
            }
            if (sqrt(m) <= MOVING) continue;
            eh += sqrt(e), nh++;
            if (v < FACE) ef += sqrt(e), nf++;
        }
        s.targets++;
    }
    s.delta_face = nf ? ef / nf : NAN;
    s.delta_head = nh ? eh / nh : NAN;
    return s;
}

static void print(const char *what, score s) {
    printf("%-36s neutral face %.3f mm (aligned %.3f), whole head %.3f mm; moving-vertex delta error face %.3f mm, "
           "whole head %.3f mm (%d targets)\n",
           what, 1e3 * s.face_raw, 1e3 * s.face_aligned, 1e3 * s.head_raw, 1e3 * s.delta_face, 1e3 * s.delta_head,
           s.targets);
}

int main(int argc, char **argv) {
    if (argc < 3) {
        fprintf(stderr, "usage: score_shapes SHAPES_DIR TRUTH_RIG [TEMPLATE_MODEL]\n");
        return 2;
    }
    frig_ctx *ctx = frig_ctx_create();
    frig_rig *truth = NULL;
    if (frig_rig_load(ctx, argv[2], &truth)) {
        fprintf(stderr, "%s\n", frig_ctx_errmsg(ctx));
        return 1;
    }
    fr_export_shapes tx;
    if (fr_export_shapes_make(ctx, truth, &tx)) return 1;
    int nv = frig_rig_vertex_count(truth);
    char path[4200];
    snprintf(path, sizeof path, "%s/neutral.obj", argv[1]);
    float *neutral = read_obj(path, nv);
    if (!neutral) {
        fprintf(stderr, "%s: no neutral of %d vertices\n", path, nv);
        return 1;
    }
    float **shapes = calloc((size_t)tx.count + 1, sizeof(float *));
    int missing = 0;
    for (int i = 0; i < tx.count; i++) {
        snprintf(path, sizeof path, "%s/%s.obj", argv[1], tx.names[i]);
        if (!(shapes[i] = read_obj(path, nv))) missing++;
    }
    if (missing) fprintf(stderr, "%d of the truth's %d targets are missing\n", missing, tx.count);
    score ours = score_shapes(truth, &tx, neutral, shapes);
    print(argv[1], ours);
    int rc = 0;
    if (argc > 3) {
        /* The bar: the true identity's model-space rig (best in-span neutral, template deltas). */
        frig_model *model = NULL;
        const char *rig_dir = strrchr(argv[2], '/');
        double *id = NULL;
        frig_rig *inspan = NULL;
        if (!frig_model_load(ctx, argv[3], &model) && rig_dir) {
            snprintf(path, sizeof path, "%.*s/../subject.json", (int)(rig_dir - argv[2]), argv[2]);
            char *text = synth_read_text(path);
            cJSON *root = text ? cJSON_Parse(text) : NULL;
            const cJSON *a = root ? cJSON_GetObjectItemCaseSensitive(root, "identity") : NULL;
            int n = frig_model_identity_count(model);
            id = calloc((size_t)n + 1, sizeof(double));
            for (int k = 0; a && k < n && k < cJSON_GetArraySize(a); k++) id[k] = cJSON_GetArrayItem(a, k)->valuedouble;
            cJSON_Delete(root);
            free(text);
            if (a && !frig_rig_from_model(ctx, model, id, &inspan)) {
                fr_export_shapes ix;
                fr_export_shapes_make(ctx, inspan, &ix);
                float **is = calloc((size_t)tx.count + 1, sizeof(float *));
                for (int i = 0; i < tx.count; i++)
                    for (int j = 0; j < ix.count; j++)
                        if (!strcmp(ix.names[j], tx.names[i])) {
                            is[i] = malloc(sizeof(float) * 3 * nv);
                            for (int k = 0; k < 3 * nv; k++) is[i][k] = frig_rig_neutral(inspan)[k] + ix.deltas[3 * (size_t)nv * j + k];
                        }
                score bar = score_shapes(truth, &tx, frig_rig_neutral(inspan), is);
                print("best in-span neutral, template deltas", bar);
                printf("bar: neutral face %s 1.5 mm; delta error %s the in-span rig's\n",
                       1e3 * ours.face_raw <= 1.5 ? "at most" : "ABOVE", ours.delta_face < bar.delta_face ? "below" : "NOT below");
                for (int i = 0; i < tx.count; i++) free(is[i]);
                free(is);
                fr_export_shapes_free(&ix);
            }
        }
        free(id);
        frig_rig_free(inspan);
        frig_model_free(model);
    }
    for (int i = 0; i < tx.count; i++) free(shapes[i]);
    free(shapes), free(neutral);
    fr_export_shapes_free(&tx);
    frig_rig_free(truth);
    frig_ctx_free(ctx);
    return rc;
}
