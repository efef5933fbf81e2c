/* Diffuse colours (Kd) from a Wavefront MTL file, for the materials a mesh uses. Internal. */
#ifndef FR_MODEL_MTL_READER_H
#define FR_MODEL_MTL_READER_H

#include <stddef.h>

/* For each of the n names, the Kd of its 'newmtl' block in text, or 'fallback' (3 values)
 * where the file has no such material or no Kd. Never fails. */
void fr_mtl_diffuse(const char *text, size_t size, const char *const *names, int n, const float fallback[3],
                    float *kd);

#endif
