// A height field as triangles (thesis 8.1): one vertex per cell, normals
// from the neighbouring heights, and each quad split along the diagonal
// that follows the surface (8.1.2): splitting every quad the same way saws
// the crests that run across that diagonal.
#pragma once

#include "render/scene.h"

namespace skidsim::render {

// The diagonal of quad (i, j)-(i+1, j+1): true to split it along
// (i, j)-(i+1, j+1), whose corners differ less in height than the other
// pair's (a crest or a valley joins similar heights along itself).
bool split_along_main_diagonal(float h00, float h10, float h01, float h11);

// The whole mesh of a field, in the field's frame: vertex j * nx + i for
// cell (i, j), then, with a skirt, a top and a bottom vertex for each edge
// cell, side by side (j = 0, i = nx - 1, j = ny - 1, i = 0); the skirt's
// triangles follow the surface's.
void build_terrain_mesh(const HeightField& field, Mesh& mesh);

// Updates the vertices of cells [i0, i1) x [j0, j1) (and the normals of
// their neighbours) and the diagonals of the quads they touch, after those
// heights changed; the mesh must have been built from a field of the same
// size and mask. Vertices of rows [j0 - 1, j1 + 1) change; returns whether
// any quad's diagonal flipped (rewritten in place in the index buffer).
// The skirt's vertices (after the nx * ny of the surface); 0 without one.
std::size_t skirt_vertex_count(const HeightField& field);

bool update_terrain_mesh(const HeightField& field, int i0, int j0, int i1, int j1, Mesh& mesh);

}  // namespace skidsim::render
