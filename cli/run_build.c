/* Which build of frig and libfrig a run's stage keys belong to. The version string alone stays
 * the same between the commits of a release, so a run folder made by an older build would keep
 * that build's outputs as "up to date" after an upgrade. The keys also hash the bytes of the
 * frig program and of the libfrig it loaded: any other build reruns every stage (the outputs
 * are the same bytes when the stages did not change), the same build keeps them. */
#define _GNU_SOURCE /* dladdr */
#include <dlfcn.h>
#include <string.h>

#include <frig/frig.h>

#include "run.h"

int run_build_hash(char out[17]) {
    run_hash h;
    run_hash_init(&h);
    run_hash_str(&h, frig_version_string());
    int bad = run_hash_file(&h, "/proc/self/exe") != 0;
    Dl_info info;
    memset(&info, 0, sizeof info);
    if (!dladdr((void *)frig_version_string, &info) || !info.dli_fname) bad = 1;
    else if (run_hash_file(&h, info.dli_fname) != 0) bad = 1;
    run_hex(h.h, out);
    return bad ? -1 : 0;
}
