/* Parameter table initialization (internal). */
#ifndef FR_CORE_PARAMS_H
#define FR_CORE_PARAMS_H
void fr_params_init(double *values);
#endif
