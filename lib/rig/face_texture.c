/* The face's base-colour texture a rig is exported and rendered with: a PNG in ICT's face UV
 * layout (the albedo the sfs stage writes to WORKSPACE/textures/albedo.png). Checked when set
 * (a PNG libfrig can decode), kept as the file's bytes so the glTF embeds them unchanged. */
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "image/image.h"
#include "io/file.h"
#include "rig/rig.h"

#define MAX_TEXTURE_FILE ((size_t)256 << 20)
#define MAX_TEXTURE_SIDE 16384

frig_status frig_rig_set_face_texture(frig_ctx *ctx, frig_rig *rig, const char *png_path) {
    if (!rig) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_rig_set_face_texture: no rig");
    if (!png_path) {
        free(rig->face_png);
        rig->face_png = NULL;
        rig->face_png_size = 0;
        return FRIG_OK;
    }
    unsigned char *data;
    size_t size;
    frig_status s = fr_read_file(ctx, png_path, MAX_TEXTURE_FILE, &data, &size);
    if (s) return s;
    if (size < 8 || memcmp(data, "\x89PNG\r\n\x1a\n", 8) != 0) {
        free(data);
        return fr_error(ctx, FRIG_ERR_UNSUPPORTED, "%s: a face texture must be a PNG file", png_path);
    }
    frig_image *img = NULL;
    s = fr_png_decode(ctx, png_path, data, size, 0, &img);
    if (!s && (img->width > MAX_TEXTURE_SIDE || img->height > MAX_TEXTURE_SIDE))
        s = fr_error(ctx, FRIG_ERR_TOO_LARGE, "%s: %d x %d pixels; a face texture may be at most %d on a side",
                     png_path, img->width, img->height, MAX_TEXTURE_SIDE);
    frig_image_free(img);
    if (s) {
        free(data);
        return s;
    }
    free(rig->face_png);
    rig->face_png = data;
    rig->face_png_size = size;
    return FRIG_OK;
}

int frig_rig_has_face_texture(const frig_rig *rig) { return rig && rig->face_png; }
