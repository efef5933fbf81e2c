/* Fixed descriptions of the status codes. */
#include "frig/frig.h"

const char *frig_strerror(frig_status status) {
    switch (status) {
    case FRIG_OK: return "no error";
    case FRIG_ERR_INVALID_ARGUMENT: return "invalid argument";
    case FRIG_ERR_NO_MEMORY: return "out of memory";
    case FRIG_ERR_IO: return "input/output error";
    case FRIG_ERR_NOT_FOUND: return "file not found";
    case FRIG_ERR_CORRUPT: return "corrupt data";
    case FRIG_ERR_TRUNCATED: return "truncated data";
    case FRIG_ERR_UNSUPPORTED: return "unsupported format";
    case FRIG_ERR_TOO_LARGE: return "over the size limit";
    case FRIG_ERR_NUMERIC: return "numerical failure";
    case FRIG_ERR_CANCELLED: return "cancelled";
    case FRIG_ERR_NO_FACE: return "no face found";
    case FRIG_ERR_TOO_FEW: return "too few usable photos";
    case FRIG_ERR_STATE: return "a required earlier stage has not run";
    case FRIG_ERR_INTERNAL: return "internal error";
    }
    return "unknown status";
}
