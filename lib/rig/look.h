/* How the rig looks when exported or rendered: each ICT material's kind, base colour, alpha
 * mode and texture. The textures are the face's base colour (frig_rig_set_face_texture) and
 * ones libfrig paints itself for the eyes (eye_texture.c): sclera with a see-through cornea,
 * iris and pupil, and the soft alpha of ICT's translucent eye overlays. Shared by the glTF and
 * OBJ writers and the renderer so that all three show the same rig. Internal. */
#ifndef FR_RIG_LOOK_H
#define FR_RIG_LOOK_H

#include <stdint.h>

#include "rig/rig.h"

typedef enum fr_material_kind {
    FR_MAT_OTHER = 0,
    FR_MAT_FACE,          /* M_Face: ICT's face UV tile, the base-colour texture's */
    FR_MAT_HEAD,          /* M_BackHead: scalp, ears, neck */
    FR_MAT_MOUTH,         /* gums and tongue */
    FR_MAT_TEETH,
    FR_MAT_SCLERA,        /* the eyeball's outer shell, with the cornea over the iris */
    FR_MAT_IRIS,          /* the inner shell: iris and pupil in front */
    FR_MAT_LACRIMAL,      /* translucent overlays ICT means to be blended: the tear film, */
    FR_MAT_EYE_BLEND,     /*   the lid-to-eyeball blend at the inner corners, */
    FR_MAT_EYE_OCCLUSION, /*   the soft shadow of the lids on the eyeball */
    FR_MAT_LASHES
} fr_material_kind;

enum { FR_ALPHA_OPAQUE = 0, FR_ALPHA_MASK = 1, FR_ALPHA_BLEND = 2 };

/* A texture: 8-bit rows from the top, sRGB colour (alpha linear), and the same as PNG bytes. */
typedef struct fr_texture {
    int width, height, channels; /* channels 3 or 4 */
    uint8_t *pixels;
    unsigned char *png;
    size_t png_size;
    char file[40]; /* its file name beside OBJ files, e.g. "frig_iris_left.png" */
} fr_texture;

typedef struct fr_material_look {
    fr_material_kind kind;
    int eye;            /* 0 left, 1 right, -1 neither */
    int omitted;        /* an eye overlay left out (export.eye_overlays 0) */
    float base[4];      /* linear base colour factor and alpha */
    float roughness;
    int alpha_mode;     /* FR_ALPHA_* */
    int double_sided;
    int texture;        /* index into the look's textures, or -1 */
} fr_material_look;

#define FR_LOOK_MAX_TEXTURES 12

typedef struct fr_rig_look {
    int material_count;
    fr_material_look *materials;
    int texture_count;
    fr_texture textures[FR_LOOK_MAX_TEXTURES];
} fr_rig_look;

/* The look of a rig under ctx's export.* parameters (eye_overlays, texture_size). */
frig_status fr_rig_look_make(frig_ctx *ctx, const frig_rig *rig, fr_rig_look *out);
void fr_rig_look_free(fr_rig_look *look);

/* The kind of an ICT material by its name, and which eye it belongs to (-1: neither). */
fr_material_kind fr_material_kind_of(const char *name, int *eye);

/* ---- textures painted for the eyes (eye_texture.c) ---- */
/* A size x size texture of material 'material' painted from the rig's neutral. */
frig_status fr_eye_texture_paint(frig_ctx *ctx, const frig_rig *rig, int material, fr_material_kind kind, int eye,
                                 int size, fr_texture *out);
void fr_texture_free(fr_texture *t);
/* Bilinear sample (u, v in the OBJ convention, v up; wraps) into rgba (0..1, sRGB colour). */
void fr_texture_sample(const fr_texture *t, double u, double v, double rgba[4]);
/* The same in linear light: each texel decoded through 'decode' (fr_srgb_decode_table) before the
 * bilinear weights, as a GPU filters an sRGB texture; alpha as it is. */
void fr_texture_sample_linear(const fr_texture *t, const float decode[256], double u, double v, double rgba[4]);

/* ---- baking into UV space (texture_bake.c) ---- */
/* out (size * size * dim floats) gets the attribute (dim floats per rig vertex) interpolated at
 * each texel centre covered by the material's triangles, each triangle in the unit UV tile its
 * lowest u lies in; covered[] (size * size) marks those texels 1, and every other texel gets the
 * value of the nearest covered one (covered[] 2). */
frig_status fr_texture_bake(frig_ctx *ctx, const fr_topology *t, int material, const float *attr, int dim, int size,
                            float *out, uint8_t *covered);

/* ---- the back of the head's look (head_texture.c) ---- */
/* How material 'head' (M_BackHead) continues 'face_tex' (the texture of material 'face') from the
 * vertices the two materials share: flat (linear) gets the face texture's mean colour over the
 * face corners at those vertices, and 'out' a size x size base-colour texture (sRGB, opaque)
 * spreading their colours over the rest of the head. Where they share no vertex flat is left as it
 * is; then, and when size is 0, 'out' stays empty (no pixels). */
frig_status fr_head_look(frig_ctx *ctx, const frig_rig *rig, int face, int head, const fr_texture *face_tex, int size,
                         float flat[3], fr_texture *out);

#endif
