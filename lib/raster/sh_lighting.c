/* Second-order spherical harmonics lighting (paper section 5.1, eq. 5.3-5.5: 9 coefficients per
 * colour channel; Ramamoorthi and Hanrahan 2001, "An efficient representation for irradiance
 * environment maps"): the real basis, its derivative and the irradiance of an ambient +
 * directional light. Shared by the synthetic renderer and the shape-from-shading stage. */
#include "raster/sh_lighting.h"

#define PI 3.14159265358979323846

void fr_sh_basis(const double n[3], double y[9]) {
    double x = n[0], yy = n[1], z = n[2];
    y[0] = 0.282094791773878;
    y[1] = 0.488602511902920 * yy;
    y[2] = 0.488602511902920 * z;
    y[3] = 0.488602511902920 * x;
    y[4] = 1.092548430592079 * x * yy;
    y[5] = 1.092548430592079 * yy * z;
    y[6] = 0.315391565252520 * (3.0 * z * z - 1.0);
    y[7] = 1.092548430592079 * x * z;
    y[8] = 0.546274215296040 * (x * x - yy * yy);
}

void fr_sh_basis_gradient(const double n[3], double y[FR_SH_COUNT], double dy[3 * FR_SH_COUNT]) {
    static const double c1 = 0.488602511902920, c2 = 1.092548430592079, c6 = 0.315391565252520,
                        c8 = 0.546274215296040;
    double x = n[0], yy = n[1], z = n[2];
    fr_sh_basis(n, y);
    for (int i = 0; i < 3 * FR_SH_COUNT; i++) dy[i] = 0.0;
    dy[3 * 1 + 1] = c1;
    dy[3 * 2 + 2] = c1;
    dy[3 * 3 + 0] = c1;
    dy[3 * 4 + 0] = c2 * yy, dy[3 * 4 + 1] = c2 * x;
    dy[3 * 5 + 1] = c2 * z, dy[3 * 5 + 2] = c2 * yy;
    dy[3 * 6 + 2] = 6.0 * c6 * z;
    dy[3 * 7 + 0] = c2 * z, dy[3 * 7 + 2] = c2 * x;
    dy[3 * 8 + 0] = 2.0 * c8 * x, dy[3 * 8 + 1] = -2.0 * c8 * yy;
}

/* E(n) = sum_k coeffs[k] Y_k(n). A directional light's radiance coefficients are Y_k(d) times
 * its irradiance, convolved with the clamped cosine (A_0 = pi, A_1 = 2 pi / 3, A_2 = pi / 4,
 * divided by pi so a surface facing the light receives 'direct'); uniform radiance gives
 * 'ambient' everywhere. */
void fr_sh_irradiance_coeffs(const double d[3], double direct, double ambient, double coeffs[9]) {
    static const double A[9] = {1.0, 2.0 / 3.0, 2.0 / 3.0, 2.0 / 3.0, 0.25, 0.25, 0.25, 0.25, 0.25};
    double y[9];
    fr_sh_basis(d, y);
    /* the truncated clamped cosine peaks at 1.0 + ~1.9%; normalize so E(d) = direct exactly */
    double peak = 0.0;
    for (int k = 0; k < 9; k++) peak += PI * A[k] * y[k] * y[k];
    for (int k = 0; k < 9; k++) coeffs[k] = direct * PI * A[k] * y[k] / peak;
    coeffs[0] += ambient / y[0];
}
