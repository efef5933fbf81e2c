/* Two doubles side by side in one vector register (GCC and Clang vector extensions), IEEE per
 * lane: the hand-vectorized loops' type (blur, weighted rows, lighting, shared solve, expressions).
 * Internal. */
#ifndef FR_CORE_V2D_H
#define FR_CORE_V2D_H

typedef double v2d __attribute__((vector_size(16)));

#endif
