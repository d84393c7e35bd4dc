// Application layer: used by tools/ and viz/ (and the Python module), never by the library modules.
// A mesh set against the render's certificates as `iaa compare` and the Python module's compare()
// do it: the IAA render and the mesh's ray cast of the same view, their per-pixel comparison
// (compare/compare.h), the diff picture and the JSON report. All but check_rays exist when
// IAA_HAVE_CGAL is defined (the ray caster, mesh/mesh_raycast.h, is CGAL's AABB tree).
#pragma once

#include <nlohmann/json.hpp>

#include <string>

#include "app/png.h"
#include "compare/compare.h"
#include "core/exec.h"
#include "mesh/mesh_raycast.h"
#include "mesh/triangle_soup.h"
#include "render/film.h"
#include "scene/scene.h"

namespace iaa::app {

/// The IAA render, the mesh's ray cast of the same view, their per-pixel comparison and the time
/// each took.
struct ComparedViews {
  Film film;
  MeshView view;
  Comparison cmp;
  double t_render = 0;
  double t_cast = 0;
};

/// Throws SettingError, naming --rays, for rays per pixel side outside 1..16.
void check_rays(int rays);

/// Renders the scene with IAA (whatever method it asks for: the certificates come from IAA) and
/// casts the mesh (valid: check_mesh) with `rays` rays per pixel side (check_rays) for the
/// covered area.
ComparedViews compare_views(const Scene& scene, const TriangleSoup& mesh, int rays,
                            const Exec& exec);

/// The diff picture of `iaa compare -o`: diff_picture() through to_byte (app/png.h).
Image8 diff_image(const ComparedViews& views);

/// The JSON report of `iaa compare --report`: counts per verdict, covered areas, times, and where
/// the lost and wrong pixels are (up to 1000 each). `mesh` names the mesh (its path).
nlohmann::json compare_report_json(const Scene& scene, const std::string& mesh,
                                   const TriangleSoup& soup, int rays, const ComparedViews& views);

}  // namespace iaa::app
