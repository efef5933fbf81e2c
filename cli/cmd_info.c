/* frig info IMAGE...: what libfrig sees in each image, or why it cannot read it. */
#include <stdio.h>

#include "cli.h"

const char cmd_info_usage[] =
    "usage: frig info IMAGE...\n"
    "\n"
    "Print one line per image: path, upright width x height, channels and bit depth in the\n"
    "file, EXIF orientation, format; or the sentence saying why it cannot be read.\n"
    "Exit status 1 if any image could not be read.\n";

static const char *format_name(frig_image_format f) {
    return f == FRIG_FORMAT_JPEG ? "JPEG" : f == FRIG_FORMAT_PNG ? "PNG" : "?";
}

int cmd_info(cli_env *env, int argc, char **argv) {
    if (argc < 1) return cli_usage_error("info", "no image given (see frig help info)");
    int bad = 0;
    for (int i = 0; i < argc; i++) {
        frig_image *img = NULL;
        frig_status s = frig_image_load(env->ctx, argv[i], FRIG_LOAD_DEFAULT, &img);
        if (s) {
            printf("%s: cannot read: %s [%s]\n", argv[i], frig_ctx_errmsg(env->ctx), frig_strerror(s));
            bad++;
            continue;
        }
        printf("%s: %dx%d, %d channel%s%s, %d-bit, orientation %d, %s\n", argv[i], frig_image_width(img),
               frig_image_height(img), frig_image_source_channels(img), frig_image_source_channels(img) == 1 ? "" : "s",
               frig_image_source_cmyk(img) ? " (CMYK)" : "", frig_image_source_bit_depth(img),
               frig_image_orientation(img), format_name(frig_image_source_format(img)));
        frig_image_free(img);
    }
    return bad ? CLI_FAILED : CLI_OK;
}
