/* A fitted mesh shown over its photo (paper sections 4.3-4.4: the reconstruction seen on the
 * input image, as in the dissertation's fitting figures): the raster's covered pixels are
 * Lambert-shaded from interpolated vertex normals and alpha-blended over the photo. */
#include <math.h>

#include "core/context.h"
#include "image/image.h"
#include "raster/draw.h"

frig_status fr_overlay_mesh(frig_ctx *ctx, frig_image *img, const fr_raster *r, const int32_t *tris,
                            const float *normals, const uint8_t rgb[3], double alpha) {
    if (r->width != img->width || r->height != img->height)
        return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT,
                        "the mesh render is %d x %d pixels but the photo is %d x %d", r->width, r->height,
                        img->width, img->height);
    const double len = sqrt(1.0 + 0.09);
    const double light[3] = {0.0, -0.3 / len, -1.0 / len};
    for (int y = 0; y < r->height; y++)
        for (int x = 0; x < r->width; x++) {
            float n[3];
            if (!fr_raster_interpolate(r, tris, x, y, normals, 3, n)) continue;
            double nl = sqrt((double)n[0] * n[0] + (double)n[1] * n[1] + (double)n[2] * n[2]);
            double lambert = nl > 0.0 ? (n[0] * light[0] + n[1] * light[1] + n[2] * light[2]) / nl : 0.0;
            double shade = 0.25 + 0.75 * (lambert > 0.0 ? lambert : 0.0);
            uint8_t c[3];
            for (int k = 0; k < 3; k++) c[k] = (uint8_t)floor(shade * rgb[k] + 0.5);
            fr_draw_blend_pixel(img, x, y, c, alpha);
        }
    return FRIG_OK;
}
