/* Point cloud region selection (paper section 5.1.3, eq. 5.15): a pixel enters the cloud when
 * its shape-from-shading error is below E_max and its depth moved less than d_max from the
 * fitted depth,
 *     inc(x, y) = (E_sfs(x, y) < E_max) && (d(x, y) < d_max),
 * with E_sfs the relative RMS residual |I - a S(n)| / |a S(n)| over the colour channels and d
 * in millimetres. Skin pixels only, one pixel in from the region's edge (mixed pixels there).
 * fr_sfs_region_narrow then keeps the narrow face's in the cloud (sfs.cloud_region, after the pose
 * is refined on all of them): the neck, ears and scalp are read at grazing angles and under the
 * chin's shadow, where the points were twice as far off (docs/sfs.md); they become the cloud's
 * margin, which retarget reads for the shape they cover (sfs.cloud_region 2, docs/retarget.md).
 * The confidence falls linearly with both (and with the view's obliquity). */
#include <math.h>
#include <string.h>

#include "sfs/sfs.h"

void fr_sfs_select_region(fr_sfs_view *v, const fr_sfs_settings *st) {
    int w = v->w, h = v->h;
    v->kept_pixels = v->margin_pixels = 0;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            size_t i = (size_t)y * w + x;
            v->kept[i] = 0;
            v->confidence[i] = 0;
            if (!v->skin[i] || v->err[i] < 0 || !(v->z[i] > 0)) continue;
            int edge = x == 0 || y == 0 || x == w - 1 || y == h - 1;
            if (!edge)
                edge = !v->skin[i - 1] || !v->skin[i + 1] || !v->skin[i - (size_t)w] || !v->skin[i + (size_t)w];
            if (edge) continue;
            double e = v->err[i], d = 1000.0 * fabs((double)v->z[i] - v->z_ref[i]);
            if (!(e < st->e_max) || !(d < st->d_max_mm)) continue;
            const float *n = v->normal + 3 * i;
            double ray[3] = {(x - v->cam.cx) / v->cam.f, (y - v->cam.cy) / v->cam.f, 1.0};
            double rl = sqrt(ray[0] * ray[0] + ray[1] * ray[1] + 1.0);
            double c = -(n[0] * ray[0] + n[1] * ray[1] + n[2] * ray[2]) / rl;
            if (!(c > 0.1)) continue;
            v->kept[i] = 1;
            v->kept_pixels++;
            double conf = (1.0 - e / st->e_max) * (1.0 - d / st->d_max_mm) * fmin(1.0, c / 0.5);
            v->confidence[i] = (float)(conf < 0 ? 0 : conf > 1 ? 1 : conf);
        }
}

void fr_sfs_region_narrow(fr_sfs_view *v, int margin) {
    size_t n = (size_t)v->w * v->h;
    v->margin_pixels = 0;
    for (size_t i = 0; i < n; i++) {
        if (!v->kept[i] || v->core[i]) continue;
        v->kept_pixels--;
        if (margin) {
            v->kept[i] = 2, v->margin_pixels++;
        } else {
            v->kept[i] = 0, v->confidence[i] = 0;
        }
    }
}
