/* The landmarks' vertices (paper section 4.3: the landmark term of eq. 4.5 pairs each detected
 * landmark with a fixed vertex of the model). ICT-FaceKit's landmark vertices follow the iBUG
 * definition on its mean face; the detector (face-api's boxes, our dlib-compatible shape
 * predictor) puts some points elsewhere. bench/landmark_calib finds, for each inner landmark, the
 * vertex within 10 mm of ICT's whose projection lies nearest, on average, to the detected point
 * on near-frontal frig synth photos (each photo's true rig, expression, pose and camera). Its
 * brows and eyes fitted human-annotated 300-W faces worse than ICT's, so only the nostrils'
 * wings (31-35) and the mouth (48-67) are taken from it (docs/fit.md "The landmarks'
 * vertices"). Off by default (fit.landmark_vertices 0): the synthetic subjects' rigs gain
 * nothing measurable with it. */
#include "fit/landmark_vertices.h"

#include <string.h>

#include "core/context.h"
#include "model/model.h"

#define ICT_VERTICES 26719

/* ICT-FaceKit's own landmark vertices (vertex_indices.json, idx_to_landmark_verts). */
static const int32_t ict_landmarks[68] = {
    1225, 1888, 1052, 367,  1719, 1722, 2199, 1447, 966,  3661, 4390, 3927, 3924, 2608, 3272, 4088, 3443,
    268,  493,  1914, 2044, 1401, 3615, 4240, 4114, 2734, 2509, 978,  4527, 4942, 4857, 1140, 2075,
    1147, 4269, 3360, 1507, 1542, 1537, 1528, 1518, 1511, 3742, 3751, 3756, 3721, 3725, 3732, 5708,
    5695, 2081, 0,    4275, 6200, 6213, 6346, 6461, 5518, 5957, 5841, 5702, 5711, 5533, 6216, 6207,
    6470, 5517, 5966};

/* Where the detector puts the nostrils and the mouth (bench/landmark_calib on frig synth subjects
 * a0-a4, b0-b3); the rest are ICT's. */
static const int32_t detected_landmarks[68] = {
    1225, 1888, 1052, 367, 1719, 1722, 2199, 1447, 966, 3661, 4390, 3927, 3924, 2608, 3272, 4088, 3443,
    268, 493, 1914, 2044, 1401, 3615, 4240, 4114, 2734, 2509, 978, 4527, 4942, 4857, 4583, 2076, 4558,
    5441, 5050, 1507, 1542, 1537, 1528, 1518, 1511, 3742, 3751, 3756, 3721, 3725, 3732, 5734, 5720, 2081,
    0, 4263, 6197, 6212, 6367, 6507, 5520, 6003, 5862, 5893, 6039, 5527, 6543, 6281, 6512, 5516, 6008};

void fr_fit_landmark_vertices(const frig_ctx *ctx, const frig_model *model, int32_t out[68]) {
    memcpy(out, model->landmarks, sizeof(int32_t) * 68);
    int ict = frig_model_vertex_count(model) == ICT_VERTICES && model->landmark_count == 68 &&
              memcmp(model->landmarks, ict_landmarks, sizeof ict_landmarks) == 0;
    if (ict && fr_param_int(ctx, FRIG_PARAM_FIT_LANDMARK_VERTICES)) memcpy(out, detected_landmarks, sizeof detected_landmarks);
}
