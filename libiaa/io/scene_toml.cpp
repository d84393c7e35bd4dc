// Scene files in TOML (docs/scene-format.md). Every key is looked up by name; whatever is left
// over in a table is an unknown key and an error that names it.
#include "io/scene_toml.h"

#include <cmath>
#include <set>
#include <sstream>
#include <string>

#include <toml++/toml.h>

#include "core/error.h"
#include "scene/scene.h"

namespace iaa {

namespace {

/// Largest image edge and pixel count a scene may ask for.
constexpr int kMaxEdge = 16384;
constexpr long long kMaxPixels = 64LL * 1024 * 1024;
constexpr double kMinFov = Camera::kMinFovDeg;
constexpr double kMaxFov = Camera::kMaxFovDeg;

/// Reads one table, remembering which keys were used so that the rest can be reported.
class TableReader {
 public:
  TableReader(const toml::table& t, std::string prefix, const std::string& source)
      : t_(t), prefix_(std::move(prefix)), source_(source) {}

  [[noreturn]] void fail(const std::string& key, const std::string& what) const {
    std::string where = source_;
    if (const toml::node* n = t_.get(key)) {
      const auto& b = n->source().begin;
      if (b.line > 0) where.append(":").append(std::to_string(b.line));
    }
    throw Error(where + ": key '" + prefix_ + key + "': " + what);
  }
  const toml::node* get(const std::string& key) {
    used_.insert(key);
    return t_.get(key);
  }
  bool has(const std::string& key) const { return t_.contains(key); }

  double number(const std::string& key, double def, double lo, double hi) {
    const toml::node* n = get(key);
    if (!n) return def;
    double v = 0;
    if (auto i = n->value_exact<int64_t>()) {
      v = static_cast<double>(*i);
    } else if (auto d = n->value_exact<double>()) {
      v = *d;
    } else {
      fail(key, "expected a number");
    }
    if (!std::isfinite(v) || v < lo || v > hi) {
      std::ostringstream m;
      m << "must be a finite number in [" << lo << ", " << hi << "], got " << v;
      fail(key, m.str());
    }
    return v;
  }
  int integer(const std::string& key, int def, int lo, int hi) {
    const toml::node* n = get(key);
    if (!n) return def;
    auto i = n->value_exact<int64_t>();
    if (!i) fail(key, "expected an integer");
    if (*i < lo || *i > hi) {
      fail(key, "must be an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) +
                    "], got " + std::to_string(*i));
    }
    return static_cast<int>(*i);
  }
  bool boolean(const std::string& key, bool def) {
    const toml::node* n = get(key);
    if (!n) return def;
    auto b = n->value_exact<bool>();
    if (!b) fail(key, "expected true or false");
    return *b;
  }
  std::string string(const std::string& key, const std::string& def) {
    const toml::node* n = get(key);
    if (!n) return def;
    auto s = n->value_exact<std::string>();
    if (!s) fail(key, "expected a string");
    return *s;
  }
  Vec3 vec3(const std::string& key, Vec3 def, double lo = -1e12, double hi = 1e12) {
    const toml::node* n = get(key);
    if (!n) return def;
    const toml::array* a = n->as_array();
    if (!a || a->size() != 3) fail(key, "expected an array of three numbers [x, y, z]");
    Vec3 v;
    for (std::size_t i = 0; i < 3; ++i) {
      const toml::node& e = *a->get(i);
      double d = 0;
      if (auto ii = e.value_exact<int64_t>()) {
        d = static_cast<double>(*ii);
      } else if (auto dd = e.value_exact<double>()) {
        d = *dd;
      } else {
        fail(key, "expected an array of three numbers [x, y, z]");
      }
      if (!std::isfinite(d) || d < lo || d > hi) {
        std::ostringstream m;
        m << "components must be finite numbers in [" << lo << ", " << hi << "]";
        fail(key, m.str());
      }
      v[static_cast<int>(i)] = d;
    }
    return v;
  }
  const toml::table* table(const std::string& key) {
    const toml::node* n = get(key);
    if (!n) return nullptr;
    const toml::table* t = n->as_table();
    if (!t) fail(key, "expected a table");
    return t;
  }
  /// Throws for the first key that was not read.
  void check_unknown() const {
    for (const auto& [k, v] : t_) {
      const std::string key(k.str());
      if (!used_.count(key)) {
        std::string where = source_;
        if (v.source().begin.line > 0)
          where.append(":").append(std::to_string(v.source().begin.line));
        where.append(": unknown key '")
            .append(prefix_)
            .append(key)
            .append("' (see docs/scene-format.md)");
        throw Error(where);
      }
    }
  }

 private:
  const toml::table& t_;
  std::string prefix_;
  const std::string& source_;
  std::set<std::string> used_;
};

/// Parses an override's value as TOML, or takes it as a string when it is not valid TOML.
void apply_override(toml::table& root, const SceneOverride& o, const std::string& source) {
  if (o.key.empty()) throw Error("--set: empty key");
  std::vector<std::string> parts;
  std::stringstream ss(o.key);
  std::string part;
  while (std::getline(ss, part, '.')) {
    if (part.empty()) throw Error("--set " + o.key + ": empty part in the dotted key");
    parts.push_back(part);
  }
  toml::table* t = &root;
  for (std::size_t i = 0; i + 1 < parts.size(); ++i) {
    toml::node* n = t->get(parts[i]);
    if (!n) {
      t->insert(parts[i], toml::table{});
      n = t->get(parts[i]);
    }
    t = n->as_table();
    if (!t) throw Error("--set " + o.key + ": '" + parts[i] + "' is not a table in " + source);
  }
  toml::table value_doc;
  try {
    value_doc = toml::parse("v = " + o.value);
  } catch (const toml::parse_error&) {
    value_doc = toml::table{};
    value_doc.insert("v", o.value);
  }
  t->insert_or_assign(parts.back(), *value_doc.get("v"));
}

/// The scene's name: the `name` key, else the file name without directory and extension.
std::string read_name(TableReader& top, const std::string& source) {
  std::string name = top.string("name", "");
  if (name.empty()) {
    name = source;
    if (auto p = name.find_last_of('/'); p != std::string::npos) name = name.substr(p + 1);
    if (auto p = name.rfind('.'); p != std::string::npos && p > 0) name = name.substr(0, p);
  }
  return name;
}

/// surface.params: finite numbers under names that are not reserved by the expression language.
Params read_params(TableReader& r, const std::string& source) {
  Params params;
  const toml::table* pt = r.table("params");
  if (!pt) return params;
  for (const auto& [k, v] : *pt) {
    const std::string name(k.str());
    double d = 0;
    if (auto i = v.value_exact<int64_t>()) {
      d = static_cast<double>(*i);
    } else if (auto f = v.value_exact<double>()) {
      d = *f;
    } else {
      throw Error(source + ": key 'surface.params." + name + "': expected a number");
    }
    if (!std::isfinite(d))
      throw Error(source + ": key 'surface.params." + name + "': must be finite");
    if (is_reserved_name(name)) {
      throw Error(source + ": key 'surface.params." + name + "': '" + name +
                  "' is a reserved name (x y z pi e or a function)");
    }
    params[name] = d;
  }
  return params;
}

/// surface.min and surface.max: a box with volume.
Box3 read_bounds(TableReader& r) {
  if (!r.has("min")) r.fail("min", "missing: the bounding box's low corner [x, y, z]");
  if (!r.has("max")) r.fail("max", "missing: the bounding box's high corner [x, y, z]");
  Box3 b;
  b.lo = r.vec3("min", {}, -1e6, 1e6);
  b.hi = r.vec3("max", {}, -1e6, 1e6);
  for (int i = 0; i < 3; ++i) {
    if (!(b.lo[i] < b.hi[i])) r.fail("max", "the box is empty: max must exceed min on every axis");
  }
  return b;
}

/// The compiled expression. A surface undefined everywhere in the box can show nothing, so it is
/// an error here rather than an empty picture later (scene.h's validate_surface). The errors of
/// both steps name the file and the key.
std::shared_ptr<const Tape> compile_surface(const Scene& s, const std::string& source) {
  std::shared_ptr<const Tape> tape;
  try {
    tape = std::make_shared<const Tape>(Tape::parse(s.expression, s.params));
  } catch (const ParseError& e) {
    throw ParseError(source + ": key 'surface.expression': " + e.bare_message(), e.line(),
                     e.column());
  }
  try {
    validate_surface(*tape, s.bounds);
  } catch (const Error& e) {
    throw Error(source + ": key 'surface.expression': " + e.what());
  }
  return tape;
}

/// [surface], which every scene has: the expression, its parameters and the bounds.
void read_surface(const toml::table* surf, const std::string& source, Scene* s) {
  if (!surf) throw Error(source + ": missing table [surface] with the expression and bounds");
  TableReader r(*surf, "surface.", source);
  if (!r.has("expression")) r.fail("expression", "missing: the surface f(x,y,z) as a string");
  s->expression = r.string("expression", "");
  s->params = read_params(r, source);
  s->bounds = read_bounds(r);
  r.check_unknown();
  s->tape = compile_surface(*s, source);
}

/// [camera]: eye, look_at, up and fov over the defaults, then checked as a whole.
void read_camera(const toml::table& cam, const std::string& source, Camera* c) {
  TableReader r(cam, "camera.", source);
  c->eye = r.vec3("eye", c->eye);
  c->look_at = r.vec3("look_at", c->look_at);
  c->up = r.vec3("up", c->up);
  c->fov_deg = r.number("fov", c->fov_deg, kMinFov, kMaxFov);
  r.check_unknown();
  try {
    validate_camera(*c);
  } catch (const Error& e) {
    throw Error(source + ": [camera]: " + e.what());
  }
}

/// [image]: size and background colour; the pixel count is bounded as well as each edge.
void read_image(const toml::table& img, const std::string& source, Scene* s) {
  TableReader r(img, "image.", source);
  s->width = r.integer("width", s->width, 1, kMaxEdge);
  s->height = r.integer("height", s->height, 1, kMaxEdge);
  s->background = r.vec3("background", s->background, 0.0, 1.0);
  if (static_cast<long long>(s->width) * s->height > kMaxPixels) {
    r.fail("height", "image too large (" + std::to_string(s->width) + "x" +
                         std::to_string(s->height) + "; at most " + std::to_string(kMaxPixels) +
                         " pixels)");
  }
  r.check_unknown();
}

/// [material]: the Phong coefficients over the defaults.
void read_material(const toml::table& mat, const std::string& source, Material* m) {
  TableReader r(mat, "material.", source);
  m->color = r.vec3("color", m->color, 0.0, 1.0);
  m->ambient = r.number("ambient", m->ambient, 0.0, 1.0);
  m->diffuse = r.number("diffuse", m->diffuse, 0.0, 1.0);
  m->specular = r.number("specular", m->specular, 0.0, 1.0);
  m->shininess = r.number("shininess", m->shininess, 1.0, 10000.0);
  r.check_unknown();
}

/// [[light]]: each light needs a position; a scene without lights gets one default light.
std::vector<PointLight> read_lights(TableReader& top, const std::string& source) {
  std::vector<PointLight> lights;
  if (const toml::node* ln = top.get("light")) {
    const toml::array* arr = ln->as_array();
    if (!arr || !arr->is_array_of_tables()) {
      throw Error(source + ": key 'light': expected an array of tables [[light]]");
    }
    int i = 0;
    for (const toml::node& e : *arr) {
      TableReader r(*e.as_table(), "light[" + std::to_string(i++) + "].", source);
      PointLight l;
      if (!r.has("position")) r.fail("position", "missing: where the light is [x, y, z]");
      l.position = r.vec3("position", l.position);
      l.color = r.vec3("color", l.color, 0.0, 100.0);
      r.check_unknown();
      lights.push_back(l);
    }
  }
  if (lights.empty()) lights.push_back(PointLight{});
  return lights;
}

/// [render]: the render settings the scene asks for, over the defaults.
void read_render(const toml::table& rt, const std::string& source, RenderSettings* st) {
  TableReader r(rt, "render.", source);
  if (r.has("method")) {
    const std::string m = r.string("method", "iaa");
    try {
      st->method = parse_method(m, &st->grid_n);
    } catch (const Error& e) {
      r.fail("method", e.what());
    }
  }
  st->grid_n = r.integer("grid", st->grid_n, 1, RenderSettings::kMaxGrid);
  st->max_level = r.integer("max_level", st->max_level, 0, RenderSettings::kMaxLevel);
  st->estimator_threshold = r.number("estimator_threshold", st->estimator_threshold, 0.0, 2.0);
  st->depth_tolerance =
      r.number("depth_tolerance", st->depth_tolerance, RenderSettings::kMinDepthTolerance,
               RenderSettings::kMaxDepthTolerance);
  st->adaptive_threshold = r.number("adaptive_threshold", st->adaptive_threshold, 0.0, 1.0);
  st->shadows = r.boolean("shadows", st->shadows);
  r.check_unknown();
}

}  // namespace

SceneOverride parse_override(std::string_view text) {
  const auto eq = text.find('=');
  if (eq == std::string_view::npos || eq == 0) {
    throw Error("--set: expected KEY=VALUE (e.g. camera.fov=30), got '" + std::string(text) + "'");
  }
  return {std::string(text.substr(0, eq)), std::string(text.substr(eq + 1))};
}

Scene parse_scene(std::string_view text, std::string_view source_view,
                  const std::vector<SceneOverride>& overrides) {
  const std::string source(source_view);
  toml::table root;
  try {
    root = toml::parse(text, source_view);
  } catch (const toml::parse_error& e) {
    throw ParseError(std::string(source) + ": " + std::string(e.description()),
                     static_cast<int>(e.source().begin.line),
                     static_cast<int>(e.source().begin.column));
  }
  for (const SceneOverride& o : overrides) apply_override(root, o, source);

  // The tables in a fixed order, so that of several errors the same one is always reported.
  Scene s;
  TableReader top(root, "", source);
  s.name = read_name(top, source);
  top.string("description", "");
  read_surface(top.table("surface"), source, &s);
  if (const toml::table* cam = top.table("camera")) read_camera(*cam, source, &s.camera);
  if (const toml::table* img = top.table("image")) read_image(*img, source, &s);
  if (const toml::table* mat = top.table("material")) read_material(*mat, source, &s.material);
  s.lights = read_lights(top, source);
  if (const toml::table* rt = top.table("render")) read_render(*rt, source, &s.settings);
  top.check_unknown();
  return s;
}

}  // namespace iaa
