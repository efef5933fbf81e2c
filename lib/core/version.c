/* Runtime version of the linked library. */
#include "frig/frig.h"

unsigned frig_version_number(void) { return FRIG_VERSION_NUMBER; }
const char *frig_version_string(void) { return FRIG_VERSION_STRING; }
