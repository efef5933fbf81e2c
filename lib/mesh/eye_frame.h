/* Where an eyeball looks: its centre and gaze axis in the mesh's own frame, for painting the
 * iris and pupil (synthetic subjects, the exported rig's eye textures). Internal. */
#ifndef FR_MESH_EYE_FRAME_H
#define FR_MESH_EYE_FRAME_H

#include "mesh/topology.h"

/* centre: the centroid of the region's vertices of xyz (3 per vertex); axis: the unit vector
 * from it through the middle of the region's most forward 5% along z (the cornea; ICT's z
 * points out of the face). Returns 0 (centre 0, axis (0, 0, 1)) when the region is absent. */
int fr_eye_frame(const fr_topology *t, const float *xyz, const char *eyeball_region, double centre[3],
                 double axis[3]);

#endif
