/* Keep the personalized rig in the model's frame. Each photo's cloud is aligned rigidly to the
 * current reconstruction and the identity fit moves the whole head, so together they can turn
 * or shift the head a little at every pass (nothing in the clouds fixes the frame). After a
 * pass the rig is moved back by the rigid transform (rotation and translation, Kabsch) that
 * best maps its face onto the face it had before (lib/mesh/point_align.c): the exported rig
 * stays where the model and the fit put it. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "mesh/point_align.h"
#include "retarget/retarget.h"
#include "rig/rig.h"

void fr_rt_anchor_frame(frig_rig *rig, int nf, const float *before) {
    double R[9], t[3], scale;
    if (!fr_point_align(before, rig->neutral, nf, 0, R, t, &scale)) return;
    int nv = rig->topo.vertex_count;
    size_t n3 = 3 * (size_t)nv;
    double y[3];
    for (int v = 0; v < nv; v++) {
        float *x = rig->neutral + 3 * (size_t)v;
        for (int i = 0; i < 3; i++) y[i] = R[3 * i] * x[0] + R[3 * i + 1] * x[1] + R[3 * i + 2] * x[2] + t[i];
        for (int i = 0; i < 3; i++) x[i] = (float)y[i];
    }
    for (int j = 0; j < rig->shape_count; j++) /* shape by shape: each a contiguous block */
        for (int v = 0; v < nv; v++) {
            float *d = rig->deltas + n3 * j + 3 * (size_t)v;
            for (int i = 0; i < 3; i++) y[i] = R[3 * i] * d[0] + R[3 * i + 1] * d[1] + R[3 * i + 2] * d[2];
            for (int i = 0; i < 3; i++) d[i] = (float)y[i];
        }
}
