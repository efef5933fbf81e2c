/* Shape error after similarity alignment: zero for a rotated, scaled, moved copy (also a
 * mirrored pose must not be "aligned" by a reflection), and the known value for a copy with
 * a known offset on every vertex. */
#include <stdlib.h>

#include "eval/shape_error.h"
#include "raster/rotation.h"
#include "testing.h"

int main(void) {
    enum { N = 500 };
    float a[3 * N], b[3 * N];
    unsigned s = 1;
    for (int i = 0; i < 3 * N; i++) {
        s = s * 1103515245u + 12345u;
        a[i] = (float)((s >> 8) % 10000) / 10000.0f - 0.5f;
    }
    double R[9];
    fr_rotation_from_euler(0.7, -0.3, 1.1, R);
    for (int v = 0; v < N; v++)
        for (int i = 0; i < 3; i++)
            b[3 * v + i] = (float)(2.5 * (R[3 * i] * a[3 * v] + R[3 * i + 1] * a[3 * v + 1] + R[3 * i + 2] * a[3 * v + 2]) +
                                   (i + 1) * 0.3);
    double e = fr_aligned_mean_distance(a, b, N);
    printf("rotated, scaled, moved copy: %.3g\n", e);
    CHECK(e < 1e-6);
    /* A mirrored copy is not a similarity of the original. */
    for (int v = 0; v < N; v++) b[3 * v] = -a[3 * v], b[3 * v + 1] = a[3 * v + 1], b[3 * v + 2] = a[3 * v + 2];
    e = fr_aligned_mean_distance(a, b, N);
    printf("mirrored copy: %.3g\n", e);
    CHECK(e > 0.05);
    /* Alternate vertices moved by +-d along x: the mean distance is d (the alignment cannot
     * absorb an offset that averages to zero and correlates with nothing). */
    for (int v = 0; v < N; v++)
        for (int i = 0; i < 3; i++) b[3 * v + i] = a[3 * v + i] + (i == 0 ? (v % 2 ? 0.01f : -0.01f) : 0);
    e = fr_aligned_mean_distance(a, b, N);
    printf("+-0.01 offsets: %.5f\n", e);
    CHECK_NEAR(e, 0.01, 5e-4);
    return test_result("test_shape_error");
}
