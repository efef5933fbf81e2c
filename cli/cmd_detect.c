/* frig detect PHOTOS... -w WORKSPACE: the detect stage from the command line (paper section
 * 4.2): faces, landmarks and each photo's status into WORKSPACE/report.json, pictures of them
 * into WORKSPACE/overlays/detect/. A new run replaces the report. */
#include <limits.h>
#include <stdio.h>
#include <string.h>

#include <frig/detect.h>
#include <frig/photoset.h>

#include "cli.h"

const char cmd_detect_usage[] =
    "usage: frig detect PHOTO|FOLDER... -w WORKSPACE [--cascades DIR] [--landmark-model FILE]\n"
    "                   [--face-models DIR] [--no-identity] [--no-overlays]\n"
    "\n"
    "Find every face in each photo (face-api's SSD detector where its networks are installed,\n"
    "else OpenCV's frontal cascade, and the profile cascade on the photo and its mirror where\n"
    "the frontal one finds nothing), 68 landmarks and a face descriptor for each, and mark the\n"
    "subject: the face nearest the set's dominant identity (then photos of other people get\n"
    "other_person: the identity step, frig help identify), or without descriptors the largest,\n"
    "most central face. A folder stands for its .jpg, .jpeg\n"
    "and .png files (not its subfolders), in name order; files named directly are taken\n"
    "whatever their extension; a path that does not exist stops the command (exit 1).\n"
    "Landmarks in STEM.pts (iBUG) or STEM.landmarks.json beside a photo replace detection\n"
    "(--set detect.user_landmarks=0 ignores them). Videos: frig run.\n"
    "\n"
    "Writes WORKSPACE/report.json (replacing any earlier report: one entry per photo with its\n"
    "status ok / no_face / face_too_small / unreadable, every face's box, score, source and 68\n"
    "landmarks in upright-photo pixels, the subject's index) and WORKSPACE/overlays/detect/\n"
    "NNN_STEM.jpg (earlier overlays there are removed). A photo that cannot be used gets its\n"
    "status and the run goes on; the exit status is 0 unless the run itself failed.\n"
    "\n"
    "  -w, --workspace DIR    the workspace folder (created if needed)\n"
    "  --cascades DIR         OpenCV's cascade folder (default /usr/share/opencv4, opencv-data)\n"
    "  --landmark-model FILE  dlib's 68-point model (default /usr/share/dlib/\n"
    "                         shape_predictor_68_face_landmarks.dat, libdlib-data)\n"
    "  --face-models DIR      face-api's model folder (default $FRIG_FACE_MODELS, else\n"
    "                         /usr/local/share/frig/face-api/model: scripts/install-deps.sh)\n"
    "  --no-identity          do not run the identity step after detection\n"
    "  --no-overlays          do not draw the overlays\n"
    "Parameters: detect.*, identity.* (frig help params).\n";

static void print_summary(const frig_photoset *set, const char *workspace, int overlays) {
    size_t counts[FRIG_PHOTO_OTHER_PERSON + 1] = {0}, faces = 0;
    for (size_t i = 0; i < frig_photoset_count(set); i++) {
        frig_photo_status s = frig_photoset_status(set, i);
        if ((unsigned)s <= FRIG_PHOTO_OTHER_PERSON) counts[s]++;
        faces += frig_photoset_face_count(set, i);
    }
    printf("%zu photos, %zu faces:", frig_photoset_count(set), faces);
    const char *sep = " ";
    for (int s = FRIG_PHOTO_OK; s <= FRIG_PHOTO_OTHER_PERSON; s++)
        if (counts[s]) printf("%s%s %zu", sep, frig_photo_status_name((frig_photo_status)s), counts[s]), sep = ", ";
    printf("\nreport: %s/report.json%s%s%s\n", workspace, overlays ? "; overlays: " : "", overlays ? workspace : "",
           overlays ? "/overlays/detect/" : "");
}

int cmd_detect(cli_env *env, int argc, char **argv) {
    const char *workspace = NULL, *cascades = NULL, *model = NULL, *face_models = NULL;
    int overlays = 1, identity = 1, rc = CLI_OK;
    cli_inputs inputs = {0};
    for (int i = 0; i < argc && rc == CLI_OK; i++) {
        const char *a = argv[i];
        int has_value = i + 1 < argc;
        if ((strcmp(a, "-w") == 0 || strcmp(a, "--workspace") == 0) && has_value) workspace = argv[++i];
        else if (strcmp(a, "--cascades") == 0 && has_value) cascades = argv[++i];
        else if (strcmp(a, "--landmark-model") == 0 && has_value) model = argv[++i];
        else if (strcmp(a, "--no-overlays") == 0) overlays = 0;
        else if (strcmp(a, "--face-models") == 0 && has_value) face_models = argv[++i];
        else if (strcmp(a, "--no-identity") == 0) identity = 0;
        else if (a[0] == '-' && a[1]) rc = cli_usage_error("detect", "unknown or incomplete option '%s'", a);
        else rc = cli_inputs_add("detect", &inputs, a, 0);
    }
    if (rc == CLI_OK && !workspace) rc = cli_usage_error("detect", "no workspace given (-w DIR)");
    if (rc == CLI_OK && inputs.count == 0) rc = cli_usage_error("detect", "no photos given");
    frig_photoset *set = NULL;
    if (rc == CLI_OK && frig_photoset_create(env->ctx, &set)) rc = cli_fail(env, "detect");
    for (size_t i = 0; rc == CLI_OK && i < inputs.count; i++)
        if (frig_photoset_add(env->ctx, set, inputs.items[i].path, NULL)) rc = cli_fail(env, "detect");
    cli_inputs_free(&inputs);
    frig_detector *det = NULL;
    if (rc == CLI_OK && frig_detector_create_with(env->ctx, cascades, model, face_models, &det))
        rc = cli_fail(env, "detect");
    if (rc == CLI_OK && frig_detect_photoset(env->ctx, det, set)) rc = cli_fail(env, "detect");
    int descriptors = 0;
    if (rc == CLI_OK) frig_detector_uses_ssd(det, &descriptors);
    /* A set with no dominant identity keeps its detections (saved below) and fails after. */
    int id_rc = rc == CLI_OK && identity && descriptors ? cli_identify(env, "detect", set) : CLI_OK;
    if (rc == CLI_OK && frig_photoset_save(env->ctx, set, workspace)) rc = cli_fail(env, "detect");
    if (rc == CLI_OK && overlays) {
        char dir[PATH_MAX];
        if (snprintf(dir, sizeof dir, "%s/overlays/detect", workspace) >= (int)sizeof dir) {
            rc = cli_usage_error("detect", "workspace path too long");
        } else {
            cli_clear_jpegs(dir);
            if (frig_detect_write_overlays(env->ctx, set, dir)) rc = cli_fail(env, "detect");
        }
    }
    if (rc == CLI_OK && !env->quiet) print_summary(set, workspace, overlays);
    if (rc == CLI_OK) rc = id_rc;
    frig_detector_free(det);
    frig_photoset_free(set);
    return rc;
}
