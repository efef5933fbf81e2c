/* Which face is the person the rig is built for (paper section 4.2 assumes one subject per
 * photo): the largest and most central usable face; faces too small to landmark reliably
 * (outer-eye-corner distance under detect.min_eye_distance) only when nothing larger exists. */
#include <math.h>

#include "detect/detector.h"

double fr_face_eye_distance(const double *lm) { return hypot(lm[72] - lm[90], lm[73] - lm[91]); }

double fr_subject_score(const double box[4], int width, int height) {
    double cx = box[0] + 0.5 * box[2], cy = box[1] + 0.5 * box[3];
    double half_diag = 0.5 * hypot((double)width, (double)height);
    double off = half_diag > 0 ? hypot(cx - 0.5 * width, cy - 0.5 * height) / half_diag : 0.0;
    if (off > 1.0) off = 1.0;
    return sqrt(fmax(0.0, box[2] * box[3])) * (1.0 - 0.5 * off);
}

long fr_choose_subject(const fr_detected_face *faces, size_t count, int width, int height, double min_eye_distance,
                       int *too_small) {
    long best = -1, best_any = -1;
    double best_s = -1, best_any_s = -1;
    for (size_t i = 0; i < count; i++) {
        double s = fr_subject_score(faces[i].box, width, height);
        if (s > best_any_s) best_any_s = s, best_any = (long)i;
        if (fr_face_eye_distance(faces[i].landmarks) >= min_eye_distance && s > best_s) best_s = s, best = (long)i;
    }
    *too_small = best < 0 && best_any >= 0;
    return best >= 0 ? best : best_any;
}
