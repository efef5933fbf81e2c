/* frig model import-ict | info | export: bring the ICT-FaceKit model in once, describe it,
 * and export the model-space rig (neutral of given identity weights + template
 * expressions) as glTF and OBJ. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include <cJSON.h>

#include "cli.h"

const char cmd_model_usage[] =
    "usage: frig model import-ict DIR [-o FILE]\n"
    "       frig model info [--model FILE]\n"
    "       frig model export [--model FILE] [--identity JSON] [--texture PNG] -o OUT|NAME.glb\n"
    "\n"
    "import-ict  read an ICT-FaceKit folder (generic_neutral_mesh.obj, identity000..099.obj,\n"
    "            the expression OBJs, vertex_indices.json) and write the binary model file\n"
    "            (default: the default model path below); prints the file's size.\n"
    "info        counts, regions and expression names of a model file.\n"
    "export      write OUT/rig.glb (glTF 2.0, ARKit-named morph targets) and OUT/shapes/*.obj\n"
    "            (neutral.obj + one OBJ per blendshape + frig.mtl + textures), or with -o\n"
    "            NAME.glb that file and NAME_shapes/ beside it; prints the target names\n"
    "            and the ARKit names the model cannot provide. --identity takes a JSON file\n"
    "            {\"identity\": [w0, w1, ...]} of identity weights in standard deviations\n"
    "            (missing values are 0; without it, the mean face). --texture: the face's\n"
    "            base-colour PNG in ICT's face UV layout (embedded in the glTF, beside the OBJs).\n"
    "\n"
    "The model is --model FILE, else $FRIG_MODEL, else $XDG_DATA_HOME/frig/ict.frigmodel,\n"
    "else ~/.local/share/frig/ict.frigmodel.\n";

static int import_ict(cli_env *env, int argc, char **argv) {
    const char *dir = NULL, *out = NULL;
    for (int i = 0; i < argc; i++) {
        if (strcmp(argv[i], "-o") == 0 && i + 1 < argc) out = argv[++i];
        else if (argv[i][0] == '-') return cli_usage_error("model import-ict", "unknown option '%s'", argv[i]);
        else if (!dir) dir = argv[i];
        else return cli_usage_error("model import-ict", "more than one folder given");
    }
    if (!dir) return cli_usage_error("model import-ict", "no ICT-FaceKit folder given");
    char path[4096];
    int rc = cli_model_path(env, "model import-ict", out, path, sizeof path);
    if (rc) return rc;
    frig_model *m = NULL;
    if (frig_model_import_ict(env->ctx, dir, &m)) return cli_fail(env, "model import-ict");
    char folder[4096];
    snprintf(folder, sizeof folder, "%s", path);
    char *slash = strrchr(folder, '/');
    if (slash && slash != folder) *slash = 0;
    if (slash && slash != folder && cli_make_dir(env, folder)) {
        frig_model_free(m);
        return CLI_FAILED;
    }
    frig_status s = frig_model_save(env->ctx, m, path);
    int nv = frig_model_vertex_count(m), nid = frig_model_identity_count(m), nexp = frig_model_expression_count(m);
    frig_model_free(m);
    if (s) return cli_fail(env, "model import-ict");
    struct stat st;
    long long bytes = stat(path, &st) == 0 ? (long long)st.st_size : -1;
    printf("%s: %lld bytes (%.1f MB): %d vertices, %d identity modes, %d expressions\n", path, bytes, bytes / 1e6, nv,
           nid, nexp);
    return CLI_OK;
}

static int info(cli_env *env, int argc, char **argv) {
    const char *given = NULL;
    for (int i = 0; i < argc; i++) {
        if (strcmp(argv[i], "--model") == 0 && i + 1 < argc) given = argv[++i];
        else return cli_usage_error("model info", "unknown argument '%s'", argv[i]);
    }
    frig_model *m = NULL;
    int rc = cli_load_model(env, "model", given, &m);
    if (rc) return rc;
    printf("vertices %d, polygons %d, triangles %d, uvs %d, materials %d\n", frig_model_vertex_count(m),
           frig_model_polygon_count(m), frig_model_triangle_count(m), frig_model_uv_count(m),
           frig_model_material_count(m));
    const int32_t *v;
    int right = frig_model_contour(m, 0, &v), left = frig_model_contour(m, 1, &v);
    printf("identity modes %d, expressions %d, landmarks 68, contour candidates %d + %d, rigid vertices %d\n",
           frig_model_identity_count(m), frig_model_expression_count(m), right, left,
           frig_model_rigid_vertices(m, &v));
    printf("materials:");
    for (int i = 0; i < frig_model_material_count(m); i++) printf(" %s", frig_model_material_name(m, i));
    printf("\nregions:\n");
    for (int r = 0; r < frig_model_region_count(m); r++) {
        const char *name;
        int first, count;
        frig_model_region(m, r, &name, &first, &count);
        printf("  %-22s vertices %5d .. %5d (%d)\n", name, first, first + count - 1, count);
    }
    printf("expressions (* = used for fitting):\n");
    for (int k = 0; k < frig_model_expression_count(m); k++)
        printf("  %s%s\n", frig_model_expression_name(m, k), frig_model_expression_fitting(m, k) ? " *" : "");
    frig_model_free(m);
    return CLI_OK;
}

/* {"identity": [w0, w1, ...]} into w (count values, the rest zero). */
static int read_identity(const char *path, double *w, int count) {
    FILE *fp = fopen(path, "rb");
    if (!fp) return cli_usage_error("model export", "%s: cannot open (%s)", path, strerror(errno));
    char *text = NULL;
    size_t size = 0, cap = 0, got;
    char chunk[4096];
    while ((got = fread(chunk, 1, sizeof chunk, fp)) > 0) {
        if (size + got + 1 > cap) {
            cap = (size + got + 1) * 2;
            char *t = realloc(text, cap);
            if (!t) break;
            text = t;
        }
        memcpy(text + size, chunk, got);
        size += got;
    }
    fclose(fp);
    cJSON *root = text ? cJSON_ParseWithLength(text, size) : NULL;
    free(text);
    const cJSON *a = cJSON_GetObjectItemCaseSensitive(root, "identity");
    int rc = CLI_OK, n = 0;
    const cJSON *e;
    if (!cJSON_IsArray(a)) rc = cli_usage_error("model export", "%s: expected {\"identity\": [numbers]}", path);
    else if (cJSON_GetArraySize(a) > count)
        rc = cli_usage_error("model export", "%s: %d identity weights, the model has %d modes", path,
                             cJSON_GetArraySize(a), count);
    else
        cJSON_ArrayForEach(e, a) {
            if (!cJSON_IsNumber(e)) {
                rc = cli_usage_error("model export", "%s: identity weight %d is not a number", path, n);
                break;
            }
            w[n++] = e->valuedouble;
        }
    cJSON_Delete(root);
    return rc;
}

static int export_cmd(cli_env *env, int argc, char **argv) {
    const char *given = NULL, *identity = NULL, *out = NULL, *texture = NULL;
    for (int i = 0; i < argc; i++) {
        if (strcmp(argv[i], "--model") == 0 && i + 1 < argc) given = argv[++i];
        else if (strcmp(argv[i], "--texture") == 0 && i + 1 < argc) texture = argv[++i];
        else if (strcmp(argv[i], "--identity") == 0 && i + 1 < argc) identity = argv[++i];
        else if (strcmp(argv[i], "-o") == 0 && i + 1 < argc) out = argv[++i];
        else return cli_usage_error("model export", "unknown argument '%s'", argv[i]);
    }
    if (!out) return cli_usage_error("model export", "no output given (-o FOLDER or -o NAME.glb)");
    frig_model *m = NULL;
    int rc = cli_load_model(env, "model", given, &m);
    if (rc) return rc;
    int k = frig_model_identity_count(m);
    double *w = calloc((size_t)k + 1, sizeof *w);
    frig_rig *rig = NULL;
    if (!w) rc = cli_usage_error("model export", "out of memory");
    if (!rc && identity) rc = read_identity(identity, w, k);
    if (!rc && frig_rig_from_model(env->ctx, m, w, &rig)) rc = cli_fail(env, "model export");
    if (!rc) rc = cli_export_rig(env, "model export", rig, out, texture);
    frig_rig_free(rig);
    free(w);
    frig_model_free(m);
    return rc;
}

int cmd_model(cli_env *env, int argc, char **argv) {
    if (argc < 1) return cli_usage_error("model", "which one: import-ict, info or export? (see frig help model)");
    if (strcmp(argv[0], "import-ict") == 0) return import_ict(env, argc - 1, argv + 1);
    if (strcmp(argv[0], "info") == 0) return info(env, argc - 1, argv + 1);
    if (strcmp(argv[0], "export") == 0) return export_cmd(env, argc - 1, argv + 1);
    return cli_usage_error("model", "unknown subcommand '%s' (import-ict, info, export)", argv[0]);
}
