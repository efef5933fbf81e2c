/* Wavefront MTL (Wavefront Technologies, "Material Library Files (.mtl)"): newmtl NAME
 * starts a material, "Kd r g b" sets its diffuse colour; everything else is ignored. */
#include <string.h>

#include "model/mtl_reader.h"
#include "model/obj_reader.h"

static const char *line_end(const char *p, const char *end) {
    while (p < end && *p != '\n') p++;
    return p;
}

static const char *skip(const char *p, const char *end) {
    while (p < end && (*p == ' ' || *p == '\t')) p++;
    return p;
}

void fr_mtl_diffuse(const char *text, size_t size, const char *const *names, int n, const float fallback[3],
                    float *kd) {
    for (int i = 0; i < n; i++) memcpy(kd + 3 * i, fallback, 3 * sizeof *kd);
    const char *p = text, *end = text + size;
    int current = -1;
    while (p < end) {
        const char *e = line_end(p, end), *s = skip(p, e);
        const char *t = e;
        while (t > s && (t[-1] == '\r' || t[-1] == ' ' || t[-1] == '\t')) t--;
        if (t - s > 7 && memcmp(s, "newmtl", 6) == 0 && (s[6] == ' ' || s[6] == '\t')) {
            const char *name = skip(s + 6, t);
            current = -1;
            for (int i = 0; i < n; i++)
                if (strlen(names[i]) == (size_t)(t - name) && memcmp(names[i], name, (size_t)(t - name)) == 0) current = i;
        } else if (current >= 0 && t - s > 3 && s[0] == 'K' && s[1] == 'd' && (s[2] == ' ' || s[2] == '\t')) {
            double c[3];
            const char *q = s + 2;
            int ok = 1;
            for (int k = 0; k < 3 && ok; k++) {
                q = skip(q, t);
                ok = fr_parse_double(&q, t, &c[k]);
            }
            if (ok)
                for (int k = 0; k < 3; k++) kd[3 * current + k] = (float)(c[k] < 0 ? 0 : c[k] > 1 ? 1 : c[k]);
        }
        p = e < end ? e + 1 : end;
    }
}
