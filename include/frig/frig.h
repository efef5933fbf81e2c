/* libfrig: personalized facial blendshape rigs from photos in the wild.
 *
 * The umbrella header: the core (versions, statuses, context, parameters) and one header
 * per concern. The conventions are written down in docs/api.md.
 *
 * Copyright (c) 2026 the libfrig authors. MIT licence (see LICENSE).
 */
#ifndef FRIG_FRIG_H
#define FRIG_FRIG_H

#include "frig/core.h"
#include "frig/image.h"
#include "frig/model.h"
#include "frig/rig.h"
#include "frig/photoset.h"
#include "frig/detect.h"
#include "frig/identity.h"
#include "frig/filter.h"
#include "frig/fit.h"
#include "frig/synth.h"
#include "frig/clouds.h"
#include "frig/retarget.h"

#endif /* FRIG_FRIG_H */
