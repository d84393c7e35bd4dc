// The CGAL peer: Mesh_3 with an implicit (labeled) domain over our point evaluator. The domain is
// {f < 0} inside the bounds, so the mesher terminates on unbounded surfaces; triangles that lie
// on the bounds' faces (the cut of that domain, not part of f = 0) are removed, leaving the
// surface clipped to the bounds as an open mesh. CGAL decides everything by point samples: it
// meets the surface where its probes see a sign change, and cannot know what it missed.
// This header is CGAL-free; mesh_cgal() exists when IAA_HAVE_CGAL is defined.
#pragma once

#include "core/exec.h"
#include "core/vec.h"
#include "expr/tape.h"
#include "mesh/triangle_soup.h"

namespace iaa {

/// Mesh_3 criteria (CGAL's names and meanings) and the domain.
struct CgalMeshSettings {
  Box3 bounds;
  /// Lower bound of facet angles in degrees (0..30; above 30 Mesh_3 may not terminate).
  double facet_angle = 25;
  /// Upper bound of the facets' circumradius (absolute length, > 0).
  double facet_size = 0.02;
  /// Upper bound of the distance between facet circumcentres and the surface (absolute, > 0).
  double facet_distance = 0.002;
  /// Relative precision of the surface intersection search (1e-12..1e-2) relative to the bounds.
  double relative_error = 1e-6;
  /// Throws SettingError naming the setting and its limits.
  void validate() const;
};

/// What mesh_cgal() reports besides the mesh.
struct CgalMeshStats {
  std::uint64_t facets = 0;        ///< facets of the complex
  std::uint64_t bound_facets = 0;  ///< of those, removed because they lie on the bounds
};

/// Meshes f = 0 inside the bounds with CGAL Mesh_3 (TBB-parallel with exec's threads). Triangles
/// are oriented with normals towards increasing f, like the octree mesher's.
TriangleSoup mesh_cgal(const Tape& tape, const CgalMeshSettings& settings, const Exec& exec = {},
                       CgalMeshStats* stats = nullptr);

}  // namespace iaa
