/* Second-order spherical harmonics lighting (paper section 5.1, eq. 5.3-5.5: 9 coefficients
 * per colour channel; Ramamoorthi and Hanrahan 2001): the real basis the synthetic renderer
 * shades with and the shape-from-shading stage fits, its derivative, and the irradiance
 * coefficients of an ambient + directional light. Irradiance E(n) = sum_k l_k Y_k(n) with n a
 * unit normal in camera coordinates (docs/camera.md, docs/synth.md). */
#ifndef FR_RASTER_SH_LIGHTING_H
#define FR_RASTER_SH_LIGHTING_H

#define FR_SH_COUNT 9

/* The 9 real basis functions at unit n. */
void fr_sh_basis(const double n[3], double y[FR_SH_COUNT]);

/* The basis and its derivative with respect to n (treated as a free 3-vector):
 * dy[3 * k + i] = d Y_k / d n_i. */
void fr_sh_basis_gradient(const double n[3], double y[FR_SH_COUNT], double dy[3 * FR_SH_COUNT]);

/* Irradiance coefficients of a distant light: 'ambient' uniform radiance plus a directional
 * light of irradiance 'direct' from unit direction d (pointing toward the light). */
void fr_sh_irradiance_coeffs(const double d[3], double direct, double ambient, double coeffs[FR_SH_COUNT]);

#endif
