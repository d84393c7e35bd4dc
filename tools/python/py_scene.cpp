// iaa.Scene and iaa.load_scene: scenes from files (with overrides, as `--set`) or built from
// Python values, which are written as TOML overrides of an empty scene so that every check and
// message is the scene file's.
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <cmath>
#include <cstdio>

#include "app/render_flags.h"
#include "app/scene_loading.h"
#include "core/error.h"
#include "io/scene_toml.h"
#include "py_common.h"

namespace iaa::py {
namespace {

/// What a scene built in Python is called in messages.
constexpr const char* kBuiltSource = "iaa.Scene";

/// A TOML basic string: quotes, backslashes and control characters escaped.
std::string toml_string(const std::string& s) {
  std::string out = "\"";
  for (unsigned char c : s) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += static_cast<char>(c);
    } else if (c < 0x20 || c == 0x7f) {
      char b[8];
      std::snprintf(b, sizeof b, "\\u%04x", c);
      out += b;
    } else {
      out += static_cast<char>(c);
    }
  }
  return out + "\"";
}

/// A TOML value from a Python one: bool, int, float (repr: exact, and inf or nan as TOML spells
/// them), str, a sequence or NumPy array (an array), a dict (an inline table); NumPy scalars too.
std::string toml_value(const pb::handle& v) {
  if (pb::isinstance<pb::array>(v) && v.cast<pb::array>().ndim() == 0) {
    return toml_value(v.attr("item")());  // a NumPy scalar array: its Python value
  }
  if (pb::hasattr(v, "dtype") && pb::str(v.attr("dtype").attr("kind")).cast<std::string>() == "b") {
    return v.cast<bool>() ? "true" : "false";  // numpy.bool_
  }
  if (pb::isinstance<pb::bool_>(v)) return v.cast<bool>() ? "true" : "false";
  if (pb::isinstance<pb::str>(v)) return toml_string(v.cast<std::string>());
  if (pb::isinstance<pb::dict>(v)) {
    std::string out = "{";
    for (const auto& [key, value] : v.cast<pb::dict>()) {
      out += (out.size() > 1 ? ", " : "") + toml_string(pb::str(key)) + " = " + toml_value(value);
    }
    return out + "}";
  }
  if (pb::isinstance<pb::sequence>(v)) {
    std::string out = "[";
    for (const pb::handle& e : pb::iter(v)) out += (out.size() > 1 ? ", " : "") + toml_value(e);
    return out + "]";
  }
  const auto obj = pb::reinterpret_borrow<pb::object>(v);
  if (pb::hasattr(v, "__index__")) return pb::str(pb::int_(obj));
  if (pb::hasattr(v, "__float__")) return pb::repr(pb::float_(obj));  // inf, nan are TOML too
  throw pb::type_error("cannot write a " + std::string(pb::str(v.get_type().attr("__name__"))) +
                       " as a scene value: use numbers, strings, booleans, lists and dicts");
}

/// Overrides as "key=value" strings: a list of such strings (taken as the command line's --set
/// takes them) or a dict {key: value} whose values are Python values (toml_value).
std::vector<std::string> override_list(const pb::object& overrides) {
  std::vector<std::string> out;
  if (overrides.is_none()) return out;
  if (pb::isinstance<pb::dict>(overrides)) {
    for (const auto& [key, value] : overrides.cast<pb::dict>()) {
      out.push_back(std::string(pb::str(key)) + "=" + toml_value(value));
    }
    return out;
  }
  if (pb::isinstance<pb::str>(overrides)) {
    throw pb::type_error("overrides: a dict {key: value} or a list of 'key=value' strings");
  }
  for (const pb::handle& o : pb::iter(overrides)) out.push_back(pb::str(o));
  return out;
}

/// Adds `table.key=value` for each item of a dict (None: nothing).
void add_table(std::vector<std::string>& out, const char* table, const pb::object& items) {
  if (items.is_none()) return;
  if (!pb::isinstance<pb::dict>(items)) {
    throw pb::type_error(std::string(table) + ": expected a dict of the [" + table +
                         "] table's keys (docs/scene-format.md)");
  }
  for (const auto& [key, value] : items.cast<pb::dict>()) {
    out.push_back(std::string(table) + "." + std::string(pb::str(key)) + "=" + toml_value(value));
  }
}

/// iaa.Scene(expression, bounds, ...): the keyword arguments as overrides of an empty scene.
PyScene build_scene(const std::string& expression, const pb::object& bounds,
                    const pb::object& params, const pb::object& camera, const pb::object& image,
                    const pb::object& material, const pb::object& lights, const pb::object& render,
                    const std::string& name) {
  std::vector<std::string> ov = {"name=" + toml_string(name),
                                 "surface.expression=" + toml_string(expression)};
  if (pb::len(bounds) != 2) throw pb::value_error("bounds: expected (min, max), two [x, y, z]");
  ov.push_back("surface.min=" + toml_value(bounds[pb::int_(0)]));
  ov.push_back("surface.max=" + toml_value(bounds[pb::int_(1)]));
  add_table(ov, "surface.params", params);
  add_table(ov, "camera", camera);
  add_table(ov, "image", image);
  add_table(ov, "material", material);
  if (!lights.is_none()) ov.push_back("light=" + toml_value(lights));
  add_table(ov, "render", render);
  return parse_py_scene("", kBuiltSource, std::move(ov));
}

pb::tuple triple(const Vec3& v) {
  return pb::make_tuple(v.x, v.y, v.z);
}

pb::dict camera_dict(const Camera& c) {
  pb::dict d;
  d["eye"] = triple(c.eye);
  d["look_at"] = triple(c.look_at);
  d["up"] = triple(c.up);
  d["fov"] = c.fov_deg;
  return d;
}

pb::dict material_dict(const Material& m) {
  pb::dict d;
  d["color"] = triple(m.color);
  d["ambient"] = m.ambient;
  d["diffuse"] = m.diffuse;
  d["specular"] = m.specular;
  d["shininess"] = m.shininess;
  return d;
}

pb::list lights_list(const std::vector<PointLight>& lights) {
  pb::list out;
  for (const PointLight& l : lights) {
    pb::dict d;
    d["position"] = triple(l.position);
    d["color"] = triple(l.color);
    out.append(d);
  }
  return out;
}

std::string scene_repr(const PyScene& s) {
  return "<iaa.Scene '" + s.scene.name + "' " + std::to_string(s.scene.width) + "x" +
         std::to_string(s.scene.height) + ": " + s.scene.expression + ">";
}

}  // namespace

PyScene parse_py_scene(std::string text, std::string source, std::vector<std::string> overrides) {
  PyScene s{std::move(text), std::move(source), std::move(overrides), {}};
  s.scene = parse_scene(s.text, s.source, app::parse_overrides(s.overrides));
  return s;
}

void bind_scene(pb::module_& m) {
  pb::class_<PyScene>(m, "Scene", R"doc(
A scene: the surface f(x, y, z) = 0 inside its bounds, the camera, the image, the material, the
lights and the render settings (docs/scene-format.md). Load one with iaa.load_scene(path), or build
one here; every keyword is a table of the scene file, and each value is checked exactly as the
file's, with the same messages (naming the key, e.g. "iaa.Scene: key 'camera.fov': ...").

    Scene(expression, bounds, *, params=None, camera=None, image=None, material=None,
          lights=None, render=None, name="scene")

expression: the surface, e.g. "x^2 + y^2 + z^2 - r^2"; bounds: ((x0, y0, z0), (x1, y1, z1));
params: {"r": 0.5}; camera: {"eye": (0, 0, 3), "look_at": (0, 0, 0), "up": (0, 1, 0), "fov": 40};
image: {"width": 500, "height": 500, "background": (1, 1, 1)}; material: {"color": ...,
"ambient": ..., "diffuse": ..., "specular": ..., "shininess": ...}; lights: [{"position": (3, 4,
5), "color": (1, 1, 1)}, ...]; render: {"method": "iaa", "max_level": 2, "shadows": False, ...}.
Raises ValueError for a bad value.)doc")
      .def(pb::init(&build_scene), pb::arg("expression"), pb::arg("bounds"), pb::kw_only(),
           pb::arg("params") = pb::none(), pb::arg("camera") = pb::none(),
           pb::arg("image") = pb::none(), pb::arg("material") = pb::none(),
           pb::arg("lights") = pb::none(), pb::arg("render") = pb::none(),
           pb::arg("name") = "scene")
      .def(
          "with_overrides",
          [](const PyScene& s, const pb::object& overrides) {
            std::vector<std::string> ov = s.overrides;
            for (std::string& o : override_list(overrides)) ov.push_back(std::move(o));
            return parse_py_scene(s.text, s.source, std::move(ov));
          },
          pb::arg("overrides"),
          "A copy with more overrides: {'camera.fov': 30} or ['camera.fov=30'] (as --set).")
      .def_property_readonly("name", [](const PyScene& s) { return s.scene.name; })
      .def_property_readonly("expression", [](const PyScene& s) { return s.scene.expression; })
      .def_property_readonly("params", [](const PyScene& s) { return s.scene.params; })
      .def_property_readonly(
          "bounds",
          [](const PyScene& s) {
            return pb::make_tuple(triple(s.scene.bounds.lo), triple(s.scene.bounds.hi));
          },
          "((x0, y0, z0), (x1, y1, z1)): nothing outside exists")
      .def_property_readonly("camera", [](const PyScene& s) { return camera_dict(s.scene.camera); })
      .def_property_readonly("width", [](const PyScene& s) { return s.scene.width; })
      .def_property_readonly("height", [](const PyScene& s) { return s.scene.height; })
      .def_property_readonly("background",
                             [](const PyScene& s) { return triple(s.scene.background); })
      .def_property_readonly("material",
                             [](const PyScene& s) { return material_dict(s.scene.material); })
      .def_property_readonly("lights", [](const PyScene& s) { return lights_list(s.scene.lights); })
      .def_property_readonly(
          "settings",
          [](const PyScene& s) { return to_python(app::render_settings_json(s.scene.settings)); },
          "the [render] settings, as the render report writes them")
      .def_property_readonly(
          "source", [](const PyScene& s) { return s.source; },
          "the file's path, or 'iaa.Scene' for a scene built in Python")
      .def_property_readonly(
          "overrides", [](const PyScene& s) { return s.overrides; },
          "the overrides applied, as 'key=value' strings")
      .def("__repr__", &scene_repr);

  m.def(
      "load_scene",
      [](const std::filesystem::path& path, const pb::object& overrides) {
        PyScene s;
        s.source = path.string();
        s.overrides = override_list(overrides);
        s.scene = app::load_scene(s.source, s.overrides, &s.text);
        return s;
      },
      pb::arg("path"), pb::arg("overrides") = pb::none(), R"doc(
Loads a scene file (TOML, docs/scene-format.md), as `iaa render SCENE --set KEY=VALUE ...` does.

overrides: a dict {"camera.fov": 30, "surface.params.r": 0.4} of Python values, or a list of
"KEY=VALUE" strings taken exactly as --set takes them. Raises ValueError with the command's
message (naming the file and the key) when the file or an override is wrong.)doc");
}

}  // namespace iaa::py
