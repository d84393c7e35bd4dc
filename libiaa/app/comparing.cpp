// A mesh against the render's certificates (comparing.h).
#include "app/comparing.h"

#include <chrono>

#include "app/meshing.h"
#include "core/error.h"
#include "render/render.h"

namespace iaa::app {

void check_rays(int rays) {
  if (rays < 1 || rays > 16)
    throw SettingError("--rays must be in 1..16, got " + std::to_string(rays));
}

#ifdef IAA_HAVE_CGAL
using meshing::seconds_since;

ComparedViews compare_views(const Scene& scene, const TriangleSoup& mesh, int rays,
                            const Exec& exec) {
  RenderSettings rs = scene.settings;
  rs.method = RenderMethod::kIaa;  // the certificates come from IAA
  ComparedViews v;
  const auto t0 = std::chrono::steady_clock::now();
  v.film = render(scene, rs, exec);
  v.t_render = seconds_since(t0);
  const auto t1 = std::chrono::steady_clock::now();
  v.view = view_mesh(mesh, scene, rays, exec);
  v.t_cast = seconds_since(t1);
  v.cmp = compare_with_film(v.film, v.view.any);
  return v;
}

Image8 diff_image(const ComparedViews& v) {
  const Film& film = v.film;
  const std::vector<Rgb> pic = diff_picture(film, v.cmp);
  Image8 img(film.width, film.height, 3);
  for (int y = 0; y < film.height; ++y) {
    for (int x = 0; x < film.width; ++x) {
      const Rgb& c = pic[film.index(x, y)];
      std::uint8_t* p = img.at(x, y);
      p[0] = to_byte(c.r), p[1] = to_byte(c.g), p[2] = to_byte(c.b);
    }
  }
  return img;
}

nlohmann::json compare_report_json(const Scene& scene, const std::string& mesh,
                                   const TriangleSoup& soup, int rays, const ComparedViews& v) {
  const Film& film = v.film;
  const CompareCounts& k = v.cmp.counts;
  double cov = 0;
  for (float c : v.view.coverage) cov += c;
  nlohmann::json j = {{"scene", scene.name},
                      {"mesh", mesh},
                      {"width", film.width},
                      {"height", film.height},
                      {"triangles", soup.triangles.size()},
                      {"rays_per_pixel", rays * rays},
                      {"pixels", k.pixels},
                      {"lost", k.lost},
                      {"wrong", k.wrong},
                      {"both_surface", k.both_surface},
                      {"both_empty", k.both_empty},
                      {"uncertain_with_mesh", k.uncertain_mesh},
                      {"uncertain_without_mesh", k.uncertain_empty},
                      {"mesh_covered_area_pixels", cov},
                      {"iaa_covered_area_pixels", film.stats.covered_area},
                      {"seconds_render", v.t_render},
                      {"seconds_mesh_cast", v.t_cast}};
  // Where they are (up to 1000 each), to look at one with `iaa inspect --pixel X,Y`.
  nlohmann::json lost = nlohmann::json::array(), wrong = nlohmann::json::array();
  for (int y = 0; y < film.height; ++y) {
    for (int x = 0; x < film.width; ++x) {
      const PixelAgreement a = v.cmp.pixel[film.index(x, y)];
      if (a == PixelAgreement::kLost && lost.size() < 1000) lost.push_back({x, y});
      if (a == PixelAgreement::kWrong && wrong.size() < 1000) wrong.push_back({x, y});
    }
  }
  j["lost_at"] = lost;
  j["wrong_at"] = wrong;
  return j;
}
#endif

}  // namespace iaa::app
