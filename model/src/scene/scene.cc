// glTF 2.0 scene loading with tinygltf. Every check that can fail on a user's file throws a
// SceneError naming the file and the problem; nothing is silently dropped.
#include "hrpp/scene/scene.h"

#include <tiny_gltf.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

namespace hrpp {
namespace {

namespace fs = std::filesystem;
using glm::dmat4;

[[noreturn]] void fail(const std::string& file, const std::string& what) {
  throw SceneError(file + ": " + what);
}

std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.9g", v);
  return buf;
}

/// The first coordinate of v outside [-limit, limit] (NaN when there is none).
float outside(const Vec3& v, float limit) {
  for (int a = 0; a < 3; ++a)
    if (!(std::fabs(v[a]) <= limit)) return v[a];
  return std::nanf("");
}

const std::string kRangeDoc = " (docs/bvh.md, \"Valid range\")";

/// Images are never needed (no textures are used), so they are not decoded.
bool skip_image(tinygltf::Image*, const int, std::string*, std::string*, int, int,
                const unsigned char*, int, void*) {
  return true;
}

const char* mode_name(int mode) {
  switch (mode) {
    case TINYGLTF_MODE_POINTS:
      return "POINTS";
    case TINYGLTF_MODE_LINE:
      return "LINES";
    case TINYGLTF_MODE_LINE_LOOP:
      return "LINE_LOOP";
    case TINYGLTF_MODE_LINE_STRIP:
      return "LINE_STRIP";
    case TINYGLTF_MODE_TRIANGLES:
      return "TRIANGLES";
    case TINYGLTF_MODE_TRIANGLE_STRIP:
      return "TRIANGLE_STRIP";
    case TINYGLTF_MODE_TRIANGLE_FAN:
      return "TRIANGLE_FAN";
    default:
      return "unknown";
  }
}

class Loader {
 public:
  Loader(const std::string& path, const tinygltf::Model& m, Scene& s) : path_(path), m_(m), s_(s) {}

  void run() {
    load_materials();
    load_lights_table();
    std::vector<int> roots;
    if (!m_.scenes.empty()) {
      int si = m_.defaultScene >= 0 ? m_.defaultScene : 0;
      if (si >= static_cast<int>(m_.scenes.size()))
        fail(path_, "default scene index " + std::to_string(si) + " out of range");
      roots = m_.scenes[si].nodes;
    } else {
      // No scenes: every node that is nobody's child is a root.
      std::vector<bool> is_child(m_.nodes.size(), false);
      for (const auto& n : m_.nodes)
        for (int c : n.children)
          if (c >= 0 && c < static_cast<int>(m_.nodes.size())) is_child[c] = true;
      for (size_t i = 0; i < m_.nodes.size(); ++i)
        if (!is_child[i]) roots.push_back(static_cast<int>(i));
    }
    for (int r : roots) visit(r, dmat4(1.0), 0);
    if (s_.triangles.empty()) fail(path_, "the default scene has no triangles");
  }

 private:
  void load_materials() {
    for (size_t i = 0; i < m_.materials.size(); ++i) {
      const auto& gm = m_.materials[i];
      Material mat;
      mat.name = gm.name.empty() ? "material_" + std::to_string(i) : gm.name;
      const auto& pbr = gm.pbrMetallicRoughness;
      if (pbr.baseColorFactor.size() == 4)
        mat.base_color = glm::vec4(pbr.baseColorFactor[0], pbr.baseColorFactor[1],
                                   pbr.baseColorFactor[2], pbr.baseColorFactor[3]);
      mat.metallic = static_cast<float>(pbr.metallicFactor);
      mat.roughness = static_cast<float>(pbr.roughnessFactor);
      if (gm.emissiveFactor.size() == 3)
        mat.emissive = Vec3(gm.emissiveFactor[0], gm.emissiveFactor[1], gm.emissiveFactor[2]);
      mat.double_sided = gm.doubleSided;
      auto ext_number = [&](const char* ext, const char* key, float* out) {
        auto it = gm.extensions.find(ext);
        if (it == gm.extensions.end() || !it->second.Has(key)) return;
        const auto& v = it->second.Get(key);
        if (!v.IsNumber())
          fail(path_,
               "material " + std::to_string(i) + ": " + ext + "." + key + " is not a number");
        *out = static_cast<float>(v.GetNumberAsDouble());
      };
      ext_number("KHR_materials_emissive_strength", "emissiveStrength", &mat.emissive_strength);
      ext_number("KHR_materials_transmission", "transmissionFactor", &mat.transmission);
      ext_number("KHR_materials_ior", "ior", &mat.ior);
      ext_number("KHR_materials_specular", "specularFactor", &mat.specular);
      for (float f : {mat.base_color.r, mat.base_color.g, mat.base_color.b, mat.metallic,
                      mat.roughness, mat.emissive.x, mat.emissive.y, mat.emissive.z,
                      mat.emissive_strength, mat.transmission, mat.ior, mat.specular})
        if (!std::isfinite(f))
          fail(path_, "material " + std::to_string(i) + " (" + mat.name +
                          ") has a NaN or infinite factor");
      s_.materials.push_back(mat);
    }
  }

  uint32_t material_index(int gltf_index, const std::string& where) {
    if (gltf_index < 0) {
      if (default_material_ < 0) {
        Material mat;
        mat.name = "default";
        mat.metallic = 0.f;
        default_material_ = static_cast<int>(s_.materials.size());
        s_.materials.push_back(mat);
      }
      return static_cast<uint32_t>(default_material_);
    }
    if (gltf_index >= static_cast<int>(m_.materials.size()))
      fail(path_, where + ": material index " + std::to_string(gltf_index) + " out of range (" +
                      std::to_string(m_.materials.size()) + " materials)");
    return static_cast<uint32_t>(gltf_index);
  }

  void load_lights_table() {
    for (const auto& l : m_.lights)
      if (l.type != "point" && l.type != "directional" && l.type != "spot")
        fail(path_, "light '" + l.name + "' has unknown type '" + l.type + "'");
  }

  static dmat4 local_matrix(const tinygltf::Node& n) {
    if (n.matrix.size() == 16) return glm::make_mat4(n.matrix.data());  // column-major
    dmat4 t(1.0), r(1.0), sc(1.0);
    if (n.translation.size() == 3)
      t[3] = glm::dvec4(n.translation[0], n.translation[1], n.translation[2], 1.0);
    if (n.rotation.size() == 4)
      r = glm::mat4_cast(glm::dquat(n.rotation[3], n.rotation[0], n.rotation[1], n.rotation[2]));
    if (n.scale.size() == 3) {
      sc[0][0] = n.scale[0];
      sc[1][1] = n.scale[1];
      sc[2][2] = n.scale[2];
    }
    return t * r * sc;
  }

  void visit(int ni, const dmat4& parent, int depth) {
    if (ni < 0 || ni >= static_cast<int>(m_.nodes.size()))
      fail(path_, "node index " + std::to_string(ni) + " out of range (" +
                      std::to_string(m_.nodes.size()) + " nodes)");
    if (on_path_.count(ni))
      fail(path_, "node " + std::to_string(ni) + " is part of a cycle in the node hierarchy");
    // glTF node hierarchies are trees: a node reached twice would be instanced twice, and
    // chains of shared children would make the walk exponential (a hang on a small file).
    if (!visited_.insert(ni).second)
      fail(path_, "node " + std::to_string(ni) +
                      " is reached more than once (glTF node hierarchies must be trees)");
    if (depth > 256)
      fail(path_, "node " + std::to_string(ni) + ": the node hierarchy is deeper than 256 levels");
    on_path_.insert(ni);
    const auto& n = m_.nodes[ni];
    if (!n.matrix.empty() && n.matrix.size() != 16)
      fail(path_, "node " + std::to_string(ni) + ": matrix must have 16 numbers");
    dmat4 world = parent * local_matrix(n);
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r)
        if (!std::isfinite(world[c][r]))
          fail(path_, "node " + std::to_string(ni) + ": transform is not finite");
    std::string name = n.name.empty() ? "node_" + std::to_string(ni) : n.name;
    if (n.mesh >= 0) add_mesh(ni, name, world);
    if (n.camera >= 0) add_camera(ni, world);
    auto ext = n.extensions.find("KHR_lights_punctual");
    if (ext != n.extensions.end()) add_light(ni, ext->second, world);
    for (int c : n.children) visit(c, world, depth + 1);
    on_path_.erase(ni);
  }

  void add_camera(int ni, const dmat4& world) {
    if (n_cameras_seen_++ > 0 || s_.camera.source.size()) return;  // first camera node wins
    int ci = m_.nodes[ni].camera;
    if (ci >= static_cast<int>(m_.cameras.size()))
      fail(path_,
           "node " + std::to_string(ni) + ": camera index " + std::to_string(ci) + " out of range");
    const auto& c = m_.cameras[ci];
    if (c.type != "perspective") return;  // orthographic: fall back to sidecar / default
    if (!(c.perspective.yfov > 0 && c.perspective.yfov < M_PI))
      fail(path_, "camera " + std::to_string(ci) + ": yfov must be in (0, pi)");
    Camera cam;
    glm::dvec3 eye(world * glm::dvec4(0, 0, 0, 1));
    glm::dvec3 fwd = glm::normalize(glm::dvec3(world * glm::dvec4(0, 0, -1, 0)));
    glm::dvec3 up = glm::normalize(glm::dvec3(world * glm::dvec4(0, 1, 0, 0)));
    cam.eye = Vec3(eye);
    cam.target = Vec3(eye + fwd);
    cam.up = Vec3(up);
    cam.fov_y_deg = static_cast<float>(glm::degrees(c.perspective.yfov));
    cam.aspect =
        c.perspective.aspectRatio > 0 ? static_cast<float>(c.perspective.aspectRatio) : 1.f;
    cam.height = 512;
    cam.width = std::max(1, static_cast<int>(std::lround(512 * cam.aspect)));
    cam.source = "gltf camera " + std::to_string(ci);
    s_.camera = cam;
  }

  void add_light(int ni, const tinygltf::Value& ext, const dmat4& world) {
    if (!ext.Has("light") || !ext.Get("light").IsNumber())
      fail(path_, "node " + std::to_string(ni) + ": KHR_lights_punctual without a light index");
    int li = ext.Get("light").GetNumberAsInt();
    if (li < 0 || li >= static_cast<int>(m_.lights.size()))
      fail(path_, "node " + std::to_string(ni) + ": light index " + std::to_string(li) +
                      " out of range (" + std::to_string(m_.lights.size()) + " lights)");
    const auto& gl = m_.lights[li];
    Light l;
    l.type = gl.type == "point"         ? Light::Type::kPoint
             : gl.type == "directional" ? Light::Type::kDirectional
                                        : Light::Type::kSpot;
    l.name = gl.name.empty() ? "light_" + std::to_string(li) : gl.name;
    l.position = Vec3(world * glm::dvec4(0, 0, 0, 1));
    glm::dvec3 d(world * glm::dvec4(0, 0, -1, 0));
    if (glm::length(d) == 0)
      fail(path_, "node " + std::to_string(ni) + ": light transform has zero scale");
    l.direction = Vec3(glm::normalize(d));
    if (gl.color.size() == 3) l.color = Vec3(gl.color[0], gl.color[1], gl.color[2]);
    l.intensity = static_cast<float>(gl.intensity);
    l.range = static_cast<float>(gl.range);
    if (!std::isfinite(l.intensity) || !std::isfinite(l.position.x) ||
        !std::isfinite(l.position.y) || !std::isfinite(l.position.z))
      fail(path_, "light '" + l.name + "' has a NaN or infinite value");
    const float bad = outside(l.position, kMaxRayOrigin);
    if (l.type != Light::Type::kDirectional && !std::isnan(bad))
      fail(path_, "node " + std::to_string(ni) + ": light '" + l.name + "' has the position " +
                      "coordinate " + num(bad) +
                      ", outside the traceable range |x| <= " + num(kMaxRayOrigin) + kRangeDoc);
    s_.lights.push_back(l);
  }

  /// Bounds-checked access to an accessor's bytes; returns (base pointer, stride).
  std::pair<const unsigned char*, size_t> accessor_data(int ai, size_t elem_size,
                                                        const std::string& what) {
    const auto& a = m_.accessors[ai];
    std::string name = what + " accessor " + std::to_string(ai);
    if (a.sparse.isSparse) fail(path_, name + ": sparse accessors are not supported");
    if (a.bufferView < 0 || a.bufferView >= static_cast<int>(m_.bufferViews.size()))
      fail(path_, name + ": bufferView index " + std::to_string(a.bufferView) + " out of range");
    const auto& bv = m_.bufferViews[a.bufferView];
    if (bv.buffer < 0 || bv.buffer >= static_cast<int>(m_.buffers.size()))
      fail(path_, name + ": buffer index " + std::to_string(bv.buffer) + " out of range");
    const auto& buf = m_.buffers[bv.buffer];
    size_t stride = bv.byteStride ? bv.byteStride : elem_size;
    if (stride < elem_size) fail(path_, name + ": byteStride smaller than the element");
    if (bv.byteOffset + bv.byteLength > buf.data.size())
      fail(path_, name + ": bufferView " + std::to_string(a.bufferView) +
                      " extends past the end of buffer " + std::to_string(bv.buffer));
    if (a.count > 0 && a.byteOffset + stride * (a.count - 1) + elem_size > bv.byteLength)
      fail(path_, name + ": " + std::to_string(a.count) +
                      " elements extend past the end of bufferView " +
                      std::to_string(a.bufferView));
    return {buf.data.data() + bv.byteOffset + a.byteOffset, stride};
  }

  std::vector<Vec3> read_positions(int ai, const std::string& where) {
    if (ai < 0 || ai >= static_cast<int>(m_.accessors.size()))
      fail(path_, where + ": POSITION accessor index " + std::to_string(ai) + " out of range");
    const auto& a = m_.accessors[ai];
    if (a.type != TINYGLTF_TYPE_VEC3 || a.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT ||
        a.normalized)
      fail(path_, where + ": POSITION accessor " + std::to_string(ai) +
                      " must be FLOAT VEC3 (quantized positions are not supported)");
    auto [base, stride] = accessor_data(ai, 12, where + " POSITION");
    std::vector<Vec3> out(a.count);
    for (size_t i = 0; i < a.count; ++i) {
      std::memcpy(&out[i], base + i * stride, 12);
      if (!std::isfinite(out[i].x) || !std::isfinite(out[i].y) || !std::isfinite(out[i].z))
        fail(path_, where + ": POSITION accessor " + std::to_string(ai) + " vertex " +
                        std::to_string(i) + " is NaN or infinite");
    }
    return out;
  }

  std::vector<uint32_t> read_indices(int ai, size_t num_vertices, const std::string& where) {
    if (ai < 0 || ai >= static_cast<int>(m_.accessors.size()))
      fail(path_, where + ": indices accessor index " + std::to_string(ai) + " out of range");
    const auto& a = m_.accessors[ai];
    size_t size = a.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE    ? 1
                  : a.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ? 2
                  : a.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT   ? 4
                                                                              : 0;
    if (a.type != TINYGLTF_TYPE_SCALAR || size == 0)
      fail(path_, where + ": indices accessor " + std::to_string(ai) +
                      " must be SCALAR unsigned byte, short or int");
    auto [base, stride] = accessor_data(ai, size, where + " indices");
    std::vector<uint32_t> out(a.count);
    for (size_t i = 0; i < a.count; ++i) {
      const unsigned char* p = base + i * stride;
      uint32_t v = size == 1 ? p[0] : size == 2 ? (p[0] | p[1] << 8) : 0;
      if (size == 4) std::memcpy(&v, p, 4);
      if (v >= num_vertices)
        fail(path_, where + ": index " + std::to_string(v) + " at position " + std::to_string(i) +
                        " of accessor " + std::to_string(ai) + " is out of range (" +
                        std::to_string(num_vertices) + " vertices)");
      out[i] = v;
    }
    return out;
  }

  void add_mesh(int ni, const std::string& node_name, const dmat4& world) {
    int mi = m_.nodes[ni].mesh;
    if (mi >= static_cast<int>(m_.meshes.size()))
      fail(path_, "node " + std::to_string(ni) + ": mesh index " + std::to_string(mi) +
                      " out of range (" + std::to_string(m_.meshes.size()) + " meshes)");
    const auto& mesh = m_.meshes[mi];
    bool flip = glm::determinant(glm::dmat3(world)) < 0;  // keeps the winding (glTF spec 3.7.4)
    for (size_t pi = 0; pi < mesh.primitives.size(); ++pi) {
      const auto& prim = mesh.primitives[pi];
      std::string where = "mesh " + std::to_string(mi) + " primitive " + std::to_string(pi);
      int mode = prim.mode < 0 ? TINYGLTF_MODE_TRIANGLES : prim.mode;
      if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP &&
          mode != TINYGLTF_MODE_TRIANGLE_FAN)
        fail(path_, where + ": mode " + std::to_string(mode) + " (" + mode_name(mode) +
                        ") is not a triangle mode; only TRIANGLES, TRIANGLE_STRIP and "
                        "TRIANGLE_FAN are supported");
      auto pos_it = prim.attributes.find("POSITION");
      if (pos_it == prim.attributes.end()) fail(path_, where + ": no POSITION attribute");
      std::vector<Vec3> pos = read_positions(pos_it->second, where);
      std::vector<uint32_t> idx;
      if (prim.indices >= 0) {
        idx = read_indices(prim.indices, pos.size(), where);
      } else {
        idx.resize(pos.size());
        for (size_t i = 0; i < idx.size(); ++i) idx[i] = static_cast<uint32_t>(i);
      }
      std::vector<std::array<uint32_t, 3>> tris;
      if (mode == TINYGLTF_MODE_TRIANGLES) {
        if (idx.size() % 3)
          fail(path_, where + ": TRIANGLES with " + std::to_string(idx.size()) +
                          " indices, not a multiple of 3");
        for (size_t i = 0; i + 2 < idx.size(); i += 3)
          tris.push_back({idx[i], idx[i + 1], idx[i + 2]});
      } else if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
        for (size_t i = 0; i + 2 < idx.size(); ++i)  // glTF 2.0 spec, 3.7.2.1
          tris.push_back({idx[i], idx[i + 1 + i % 2], idx[i + 2 - i % 2]});
      } else {
        for (size_t i = 1; i + 1 < idx.size(); ++i) tris.push_back({idx[i], idx[i + 1], idx[0]});
      }
      std::vector<Vec3> wpos(pos.size());
      for (size_t i = 0; i < pos.size(); ++i) {
        glm::dvec3 p(world * glm::dvec4(glm::dvec3(pos[i]), 1.0));
        wpos[i] = Vec3(p);
        if (!std::isfinite(wpos[i].x) || !std::isfinite(wpos[i].y) || !std::isfinite(wpos[i].z))
          fail(path_,
               where + ": vertex " + std::to_string(i) + " is not finite after the node transform");
        const float bad = outside(wpos[i], kMaxSceneCoordinate);
        if (!std::isnan(bad))
          fail(path_, "node " + std::to_string(ni) + " (" + node_name + ") " + where + ": vertex " +
                          std::to_string(i) + " has the world coordinate " + num(bad) +
                          ", outside the traceable range |x| <= " + num(kMaxSceneCoordinate) +
                          kRangeDoc);
      }
      MeshRange range;
      range.name = node_name;
      range.first = static_cast<uint32_t>(s_.triangles.size());
      range.count = static_cast<uint32_t>(tris.size());
      range.material = material_index(prim.material, where);
      for (size_t ti = 0; ti < tris.size(); ++ti) {
        const auto& t = tris[ti];
        Triangle tri{wpos[t[0]], wpos[t[1]], wpos[t[2]]};
        if (flip) std::swap(tri.v1, tri.v2);
        const double twice_area =
            glm::length(glm::cross(DVec3(tri.v1) - DVec3(tri.v0), DVec3(tri.v2) - DVec3(tri.v0)));
        if (twice_area > 0 && twice_area < kMinTwiceArea)
          fail(path_, "node " + std::to_string(ni) + " (" + node_name + ") " + where +
                          ": triangle " + std::to_string(ti) + " has twice the area " +
                          num(twice_area) + ", below the smallest traceable " + num(kMinTwiceArea) +
                          " (zero-area triangles are accepted)" + kRangeDoc);
        if (tri.degenerate()) ++s_.degenerate_triangles;
        s_.bounds.grow(tri.bounds());
        s_.triangles.push_back(tri);
        s_.tri_material.push_back(range.material);
      }
      s_.meshes.push_back(range);
    }
  }

  const std::string& path_;
  const tinygltf::Model& m_;
  Scene& s_;
  std::set<int> on_path_;
  std::set<int> visited_;
  int n_cameras_seen_ = 0;
  int default_material_ = -1;
};

std::array<float, 3> read_vec3(const nlohmann::json& j, const char* key, const std::string& file) {
  if (!j.contains(key)) fail(file, std::string("missing key '") + key + "'");
  const auto& v = j[key];
  if (!v.is_array() || v.size() != 3) fail(file, std::string("'") + key + "' must be 3 numbers");
  std::array<float, 3> out;
  for (int i = 0; i < 3; ++i) {
    if (!v[i].is_number()) fail(file, std::string("'") + key + "' must be 3 numbers");
    out[i] = v[i].get<float>();
    if (!std::isfinite(out[i])) fail(file, std::string("'") + key + "' is not finite");
  }
  return out;
}

}  // namespace

const char* light_type_name(Light::Type t) {
  switch (t) {
    case Light::Type::kPoint:
      return "point";
    case Light::Type::kDirectional:
      return "directional";
    case Light::Type::kSpot:
      return "spot";
  }
  return "?";
}

std::vector<uint32_t> Scene::emissive_triangles() const {
  std::vector<uint32_t> out;
  for (uint32_t i = 0; i < triangles.size(); ++i)
    if (material_of(i).is_emissive() && !triangles[i].degenerate()) out.push_back(i);
  return out;
}

Camera load_camera_sidecar(const std::string& path) {
  std::ifstream in(path);
  if (!in) fail(path, "cannot open camera file");
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    fail(path, std::string("bad JSON: ") + e.what());
  }
  if (!j.is_object()) fail(path, "camera file must hold a JSON object");
  Camera c;
  auto e = read_vec3(j, "eye", path), t = read_vec3(j, "target", path),
       u = read_vec3(j, "up", path);
  c.eye = Vec3(e[0], e[1], e[2]);
  c.target = Vec3(t[0], t[1], t[2]);
  c.up = Vec3(u[0], u[1], u[2]);
  if (c.eye == c.target) fail(path, "eye and target coincide");
  if (glm::length(glm::cross(c.target - c.eye, c.up)) == 0)
    fail(path, "'up' is zero or parallel to the view direction");
  if (!j.contains("fov_y_deg") || !j["fov_y_deg"].is_number())
    fail(path, "missing number 'fov_y_deg'");
  c.fov_y_deg = j["fov_y_deg"].get<float>();
  if (!(c.fov_y_deg > 0 && c.fov_y_deg < 180)) fail(path, "'fov_y_deg' must be in (0, 180)");
  if (j.contains("aspect")) {
    if (!j["aspect"].is_number() || !(j["aspect"].get<float>() > 0))
      fail(path, "'aspect' must be a positive number");
    c.aspect = j["aspect"].get<float>();
  }
  if (j.contains("image_size")) {
    const auto& s = j["image_size"];
    if (!s.is_array() || s.size() != 2 || !s[0].is_number_integer() || !s[1].is_number_integer() ||
        s[0].get<int>() <= 0 || s[1].get<int>() <= 0)
      fail(path, "'image_size' must be two positive integers");
    c.width = s[0].get<int>();
    c.height = s[1].get<int>();
  } else {
    c.height = 512;
    c.width = std::max(1, static_cast<int>(std::lround(512 * c.aspect)));
  }
  c.source = "sidecar " + fs::path(path).filename().string();
  return c;
}

Camera default_camera(const Aabb& b) {
  Camera c;
  c.target = b.center();
  float radius = 0.5f * b.diagonal();
  c.fov_y_deg = 45.f;
  float dist = radius / std::sin(glm::radians(c.fov_y_deg * 0.5f));
  c.eye = c.target + Vec3(0.f, 0.f, std::max(dist, 1e-3f));
  c.up = Vec3(0, 1, 0);
  c.source = "computed default";
  return c;
}

namespace {

/// Reads an external buffer file: only regular files (a hostile URI naming a FIFO or a device
/// such as /dev/stdin or /dev/zero would block or never end).
bool read_regular_file(std::vector<unsigned char>* out, std::string* err,
                       const std::string& filepath, void* allow) {
  if (!allow) {
    if (err) *err += "external file '" + filepath + "' not read (scene loaded from memory)\n";
    return false;
  }
  std::error_code ec;
  if (!fs::is_regular_file(filepath, ec)) {
    if (err) *err += "'" + filepath + "' is not a regular file\n";
    return false;
  }
  return tinygltf::ReadWholeFile(out, err, filepath, nullptr);
}

/// Whether an external file exists, without opening it (tinygltf's own check fopen()s the file,
/// which blocks forever on a FIFO).
bool file_exists(const std::string& path, void*) {
  std::error_code ec;
  return fs::exists(path, ec);
}

/// Parses glTF bytes (binary when they start with "glTF", else JSON); `path` names them in
/// messages, `base_dir` resolves external buffer URIs.
Scene load_scene_bytes(const unsigned char* data, size_t size, const std::string& path,
                       const std::string& base_dir, bool read_files) {
  const bool binary = size >= 4 && std::memcmp(data, "glTF", 4) == 0;
  if (binary && size >= 8) {  // tinygltf would also take a glTF 1.0 binary (version 1)
    const uint32_t version = data[4] | data[5] << 8 | data[6] << 16 | uint32_t{data[7]} << 24;
    if (version != 2)
      fail(path, "binary glTF version " + std::to_string(version) + " is not supported (only 2)");
  }
  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(skip_image, nullptr);
  static int allow_token;
  loader.SetFsCallbacks({&file_exists, &tinygltf::ExpandFilePath, &read_regular_file,
                         &tinygltf::WriteWholeFile, read_files ? &allow_token : nullptr});
  tinygltf::Model model;
  std::string err, warn;
  bool ok =
      binary ? loader.LoadBinaryFromMemory(&model, &err, &warn, data,
                                           static_cast<unsigned int>(size), base_dir)
             : loader.LoadASCIIFromString(&model, &err, &warn, reinterpret_cast<const char*>(data),
                                          static_cast<unsigned int>(size), base_dir);
  if (!ok) {
    while (!err.empty() && (err.back() == '\n' || err.back() == ' ')) err.pop_back();
    fail(path, "invalid glTF: " + (err.empty() ? std::string("tinygltf could not parse it") : err));
  }

  Scene s;
  s.path = path;
  s.name = fs::path(path).stem().string();
  Loader(path, model, s).run();
  return s;
}

/// The scene must be traceable in float32: its diagonal and its camera finite.
void check_extent(const Scene& s) {
  const Camera& c = s.camera;
  auto finite = [](const Vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
  };
  if (!std::isfinite(s.bounds.diagonal()) || !finite(c.eye) || !finite(c.target))
    fail(s.path,
         "coordinates too large: the scene's bounds or its camera overflow float32 "
         "(bounds (" +
             std::to_string(s.bounds.lo.x) + ", " + std::to_string(s.bounds.lo.y) + ", " +
             std::to_string(s.bounds.lo.z) + ") to (" + std::to_string(s.bounds.hi.x) + ", " +
             std::to_string(s.bounds.hi.y) + ", " + std::to_string(s.bounds.hi.z) + "))");
  for (const auto& [what, v] : {std::pair{"eye", c.eye}, std::pair{"target", c.target}}) {
    const float bad = outside(v, kMaxRayOrigin);
    if (!std::isnan(bad))
      fail(s.path, "camera (" + c.source + "): the " + what + " coordinate " + num(bad) +
                       " is outside the traceable range |x| <= " + num(kMaxRayOrigin) + kRangeDoc);
  }
}

}  // namespace

Scene load_scene_from_memory(const unsigned char* data, size_t size, const std::string& name) {
  if (size > 0xFFFFFFFFu) fail(name, "larger than 4 GB");
  Scene s = load_scene_bytes(data, size, name, "", false);
  if (s.camera.source.empty()) s.camera = default_camera(s.bounds);
  check_extent(s);
  return s;
}

Scene load_scene(const std::string& path) {
  if (!fs::exists(path)) fail(path, "no such file");
  if (fs::is_directory(path)) fail(path, "is a directory, not a scene file");
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path, "cannot open file");
  std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(in)),
                                   std::istreambuf_iterator<char>());
  if (in.bad()) fail(path, "read error");
  if (bytes.size() > 0xFFFFFFFFu) fail(path, "larger than 4 GB");
  const bool binary = bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0;
  if (fs::path(path).extension() == ".glb" && !binary)
    fail(path, "not a binary glTF file (bad magic)");

  Scene s = load_scene_bytes(bytes.data(), bytes.size(), path,
                             fs::path(path).parent_path().string(), true);
  if (s.camera.source.empty()) {
    fs::path sidecar = fs::path(path).parent_path() / (s.name + ".camera.json");
    s.camera =
        fs::exists(sidecar) ? load_camera_sidecar(sidecar.string()) : default_camera(s.bounds);
  }
  check_extent(s);
  return s;
}

void keep_meshes(Scene* scene, const std::vector<std::string>& names) {
  for (const std::string& n : names) {
    bool found = false;
    for (const MeshRange& m : scene->meshes) found = found || m.name == n;
    if (!found) {
      std::string known;
      for (const MeshRange& m : scene->meshes) known += (known.empty() ? "" : ", ") + m.name;
      throw std::invalid_argument("no mesh '" + n + "' in " + scene->path +
                                  " (its meshes: " + known + ")");
    }
  }
  std::vector<Triangle> tris;
  std::vector<uint32_t> mats;
  std::vector<MeshRange> meshes;
  Aabb bounds;
  uint32_t degenerate = 0;
  for (const MeshRange& m : scene->meshes) {
    if (std::find(names.begin(), names.end(), m.name) == names.end()) continue;
    MeshRange k = m;
    k.first = uint32_t(tris.size());
    for (uint32_t i = m.first; i < m.first + m.count; ++i) {
      tris.push_back(scene->triangles[i]);
      mats.push_back(scene->tri_material[i]);
      degenerate += tris.back().degenerate();
      bounds.grow(tris.back().bounds());
    }
    meshes.push_back(k);
  }
  scene->triangles = std::move(tris);
  scene->tri_material = std::move(mats);
  scene->meshes = std::move(meshes);
  scene->bounds = bounds;
  scene->degenerate_triangles = degenerate;
}

}  // namespace hrpp
