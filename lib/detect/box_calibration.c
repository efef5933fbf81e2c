/* The map from OpenCV cascade boxes to the boxes of dlib's HOG face detector, on which dlib's
 * 68-point predictor was trained (paper section 4.2: the landmarks need the box convention of
 * the model's training). dlib_box = (x + a w, y + b h, c w, d h), per cascade. */
#include <math.h>

#include "detect/detector.h"

/* Least squares over the faces of ../shared/photos (all 738) that both our cascade (1.1 / 3 /
 * 30, each cascade run on every photo for the fit) and dlib's HOG detector (upsampled once)
 * find, matched one to one by IoU >= 0.3: a = sum w (X - x) / sum w^2, c = sum w W / sum w^2,
 * likewise b, d on the y axis, with (X, Y, W, H) dlib's box (W = right - left + 1). Measured
 * by bench/box_calibration.sh (it prints these rows): 754 frontal faces (mean IoU with dlib's
 * box 0.745 raw -> 0.824 calibrated), 333 profile (0.542 -> 0.737), 258 mirrored profile
 * (0.522 -> 0.734). The mirrored map agrees with the profile map reflected (a' = 1 - a - c =
 * 0.237 vs 0.229); the profile fits rest mostly on half-turned faces, which dlib also finds. */
static const fr_box_map maps[3] = {
    /* frontal (alt2) */ {0.0382, 0.1188, 0.9325, 0.9320},
    /* profile */ {-0.0438, 0.1816, 0.8067, 0.8062},
    /* profile on the mirrored photo */ {0.2286, 0.2056, 0.7693, 0.7689},
};

/* face-api's SSD boxes to dlib's, fitted the same way over the 725 faces the SSD (photos decoded
 * as jpeg-js does) and dlib's HOG detector both find in the 738 photos (bench/ssd_detect.sh
 * prints the row): mean IoU with dlib's box 0.722 raw -> 0.768 mapped. The SSD's boxes are
 * taller (they take in the forehead) and a little narrower than dlib's. */
static const fr_box_map ssd_map = {-0.0155, 0.1014, 1.0476, 0.8532};

/* A face's 68 points to dlib's HOG box of that face: the box's corner at the centroid of the
 * inner points (17-67) plus (a s, b s), its sides (c s, d s), s the square root of the area of
 * the points' bounding box. Fitted as above (a = sum s (X - mx) / sum s^2, ...) on dlib's own
 * boxes and the points its predictor finds in them, 788 faces of ../shared/photos (bench/
 * ssd_landmarks fit prints the row; mean IoU with dlib's box 0.834). On a turned face the box
 * follows the features (eyes, nose, mouth) where a detector's box covers the head, which is
 * the box the predictor was trained on. */
static const double landmark_box[4] = {-0.5221, -0.5262, 1.0643, 1.0637};

void fr_box_from_landmarks(const double *lm, double box[4]) {
    double x0 = lm[0], x1 = lm[0], y0 = lm[1], y1 = lm[1], mx = 0, my = 0;
    for (int k = 0; k < 68; k++) {
        double x = lm[2 * k], y = lm[2 * k + 1];
        x0 = x < x0 ? x : x0, x1 = x > x1 ? x : x1, y0 = y < y0 ? y : y0, y1 = y > y1 ? y : y1;
        if (k >= 17) mx += x / 51, my += y / 51;
    }
    double s = sqrt((x1 - x0) * (y1 - y0));
    box[0] = mx + landmark_box[0] * s;
    box[1] = my + landmark_box[1] * s;
    box[2] = landmark_box[2] * s;
    box[3] = landmark_box[3] * s;
}

fr_box_map fr_box_map_for(int source) {
    if (source >= FRIG_FACE_FRONTAL && source <= FRIG_FACE_PROFILE_MIRRORED) return maps[source];
    if (source == FRIG_FACE_SSD) return ssd_map;
    return (fr_box_map){0.0, 0.0, 1.0, 1.0};
}

void fr_box_map_apply(const fr_box_map *m, const double raw[4], double out[4]) {
    double w = raw[2], h = raw[3];
    out[0] = raw[0] + m->a * w;
    out[1] = raw[1] + m->b * h;
    out[2] = m->c * w;
    out[3] = m->d * h;
}

void fr_box_to_ltrb(const double box[4], double ltrb[4]) {
    ltrb[0] = box[0];
    ltrb[1] = box[1];
    ltrb[2] = box[0] + box[2] - 1.0;
    ltrb[3] = box[1] + box[3] - 1.0;
}

/* How far a face is turned, from its 68 points: the nose tip's (30) place between the face's
 * outline at the nose's height (mean of points 1-3 and of 13-15), along the eye line (36 ->
 * 45), mapped to [-1, 1]: 0 when the nose is midway, +-1 when it reaches the outline. */
double fr_landmarks_turn(const double *lm) {
    double ex = lm[90] - lm[72], ey = lm[91] - lm[73], n = hypot(ex, ey);
    if (!(n > 0)) return 0;
    ex /= n, ey /= n;
    double l = 0, r = 0;
    for (int k = 1; k <= 3; k++) l += (lm[2 * k] * ex + lm[2 * k + 1] * ey) / 3;
    for (int k = 13; k <= 15; k++) r += (lm[2 * k] * ex + lm[2 * k + 1] * ey) / 3;
    double nose = lm[60] * ex + lm[61] * ey;
    if (!(r - l > 0)) return 0;
    double t = 2 * (nose - l) / (r - l) - 1;
    return t < -1 ? -1 : t > 1 ? 1 : t;
}
