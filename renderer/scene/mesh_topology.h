// Whether a mesh encloses a volume: what tells a glass solid from a thin glass wall.
#pragma once

#include "scene/scene.h"

namespace veach {

// True when every edge of the mesh's triangles, with corners welded by exact position, is shared
// by an even number of triangles (two on a manifold surface): the surface has no boundary, so it
// encloses an interior that a refracted ray must leave through again. A single plane, an open
// box or a window pane modelled as one sheet has boundary edges and is not closed.
bool is_closed_mesh(const Mesh& mesh);

}  // namespace veach
