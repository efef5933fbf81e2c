/* Example: make an image, save it atomically as PNG, load it back, print what libfrig sees.
 * Build against an installed libfrig:
 *   cc load_image.c $(pkg-config --cflags --libs frig) -o load_image
 */
#include <stdio.h>

#include <frig/frig.h>

int main(int argc, char **argv) {
    if (argc != 2) {
        fprintf(stderr, "usage: %s OUT.png\n", argv[0]);
        return 2;
    }
    if (frig_version_number() / 10000 != FRIG_VERSION_MAJOR) {
        fprintf(stderr, "libfrig %s does not match the headers (%s)\n", frig_version_string(), FRIG_VERSION_STRING);
        return 1;
    }
    frig_ctx *ctx = frig_ctx_create();
    frig_image *img = NULL, *back = NULL;
    int rc = 1;
    if (frig_image_create(ctx, 64, 32, 3, &img) != FRIG_OK) goto done;
    uint8_t *px = frig_image_pixels_mutable(img);
    for (int y = 0; y < 32; y++)
        for (int x = 0; x < 64; x++) {
            uint8_t *p = px + (size_t)y * frig_image_stride(img) + 3 * (size_t)x;
            p[0] = (uint8_t)(x * 4), p[1] = (uint8_t)(y * 8), p[2] = 128;
        }
    if (frig_image_save_png(ctx, img, argv[1]) != FRIG_OK) goto done;
    if (frig_image_load(ctx, argv[1], FRIG_LOAD_DEFAULT, &back) != FRIG_OK) goto done;
    printf("%s: %dx%d, %d channels (libfrig %s)\n", argv[1], frig_image_width(back), frig_image_height(back),
           frig_image_channels(back), frig_version_string());
    rc = 0;
done:
    if (rc) fprintf(stderr, "error: %s\n", frig_ctx_errmsg(ctx));
    frig_image_free(img);
    frig_image_free(back);
    frig_ctx_free(ctx);
    return rc;
}
