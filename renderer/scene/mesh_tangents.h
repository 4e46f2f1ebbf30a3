// Per-vertex tangent frames for tangent-space normal maps, when a file has no TANGENT.
#pragma once

#include "scene/scene.h"

namespace veach {

// Fills mesh->tangents and tangent_signs from texture coordinate set `texcoord` (0 or 1), the
// way MikkTSpace does on ordinary meshes (vertices already split at UV seams, as exporters write
// them): each triangle's dP/du and dP/dv, normalised, are accumulated at its corners weighted by
// the corner angle; the tangent is then made orthogonal to the vertex normal (Gram-Schmidt) and
// the sign says whether cross(normal, tangent) runs along the bitangent. In glTF's convention v
// grows downward in the image, so the normal map's +Y (green) is -dP/dv. Does nothing when the
// mesh has no such UVs; vertices whose triangles are all UV-degenerate get any unit tangent
// orthogonal to the normal.
void generate_tangents(Mesh* mesh, int texcoord);

}  // namespace veach
