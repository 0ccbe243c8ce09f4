#include "scene_builder.h"

#include <cmath>
#include <cstring>
#include <fstream>

namespace hrpp::test {

SceneBuilder::SceneBuilder() {
  j_["asset"] = {{"version", "2.0"}};
  j_["scene"] = 0;
  j_["scenes"] = {{{"nodes", nlohmann::json::array()}}};
  j_["nodes"] = nlohmann::json::array();
  j_["meshes"] = nlohmann::json::array();
  j_["materials"] = nlohmann::json::array();
  j_["bufferViews"] = nlohmann::json::array();
  j_["accessors"] = nlohmann::json::array();
  j_["extensionsUsed"] = {"KHR_lights_punctual", "KHR_materials_emissive_strength",
                          "KHR_materials_transmission", "KHR_materials_ior"};
  j_["extensions"]["KHR_lights_punctual"]["lights"] = nlohmann::json::array();
  camera(Vec3(0, 2, 6), Vec3(0, 0.5f, 0), Vec3(0, 1, 0), 45, 64, 64);
}

int SceneBuilder::material(const MaterialSpec& m) {
  nlohmann::json mj = {{"name", m.name},
                       {"pbrMetallicRoughness",
                        {{"baseColorFactor", {m.base.x, m.base.y, m.base.z, 1.0}},
                         {"metallicFactor", m.metallic},
                         {"roughnessFactor", m.roughness}}},
                       {"emissiveFactor", {m.emissive.x, m.emissive.y, m.emissive.z}},
                       {"doubleSided", m.double_sided}};
  if (m.emissive_strength != 1.f)
    mj["extensions"]["KHR_materials_emissive_strength"] = {
        {"emissiveStrength", m.emissive_strength}};
  if (m.transmission > 0) {
    mj["extensions"]["KHR_materials_transmission"] = {{"transmissionFactor", m.transmission}};
    mj["extensions"]["KHR_materials_ior"] = {{"ior", m.ior}};
  }
  j_["materials"].push_back(mj);
  return static_cast<int>(j_["materials"].size()) - 1;
}

uint32_t SceneBuilder::mesh(const std::string& name, const std::vector<Vec3>& verts,
                            const std::vector<uint32_t>& indices, int material) {
  auto view = [&](const void* data, size_t bytes) {
    while (bin_.size() % 4) bin_.push_back(0);
    const size_t off = bin_.size();
    bin_.resize(off + bytes);
    std::memcpy(bin_.data() + off, data, bytes);
    j_["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", off}, {"byteLength", bytes}});
    return static_cast<int>(j_["bufferViews"].size()) - 1;
  };
  Vec3 lo(kInf), hi(-kInf);
  for (const Vec3& v : verts) {
    lo = glm::min(lo, v);
    hi = glm::max(hi, v);
  }
  const int pv = view(verts.data(), verts.size() * sizeof(Vec3));
  j_["accessors"].push_back({{"bufferView", pv},
                             {"componentType", 5126},
                             {"count", verts.size()},
                             {"type", "VEC3"},
                             {"min", {lo.x, lo.y, lo.z}},
                             {"max", {hi.x, hi.y, hi.z}}});
  const int pa = static_cast<int>(j_["accessors"].size()) - 1;
  const int iv = view(indices.data(), indices.size() * 4);
  j_["accessors"].push_back(
      {{"bufferView", iv}, {"componentType", 5125}, {"count", indices.size()}, {"type", "SCALAR"}});
  const int ia = static_cast<int>(j_["accessors"].size()) - 1;
  nlohmann::json prim = {
      {"attributes", {{"POSITION", pa}}}, {"indices", ia}, {"mode", 4}, {"material", material}};
  nlohmann::json m;
  m["primitives"] = nlohmann::json::array({prim});
  j_["meshes"].push_back(m);
  j_["nodes"].push_back({{"name", name}, {"mesh", j_["meshes"].size() - 1}});
  j_["scenes"][0]["nodes"].push_back(j_["nodes"].size() - 1);
  const uint32_t first = tris_;
  tris_ += static_cast<uint32_t>(indices.size() / 3);
  return first;
}

uint32_t SceneBuilder::quad(const std::string& name, Vec3 c, Vec3 a, Vec3 b, Vec3 facing,
                            int material) {
  std::vector<Vec3> v = {c, c + a, c + a + b, c + b};
  std::vector<uint32_t> idx = {0, 1, 2, 0, 2, 3};
  if (glm::dot(glm::cross(a, b), facing) < 0) idx = {0, 2, 1, 0, 3, 2};
  return mesh(name, v, idx, material);
}

uint32_t SceneBuilder::sphere(const std::string& name, Vec3 centre, float radius, int material,
                              int stacks, int slices) {
  std::vector<Vec3> v;
  for (int i = 0; i <= stacks; ++i)
    for (int k = 0; k <= slices; ++k) {
      const float th = 3.14159265f * i / stacks, ph = 6.28318531f * k / slices;
      v.push_back(centre + radius * Vec3(std::sin(th) * std::cos(ph), std::cos(th),
                                         std::sin(th) * std::sin(ph)));
    }
  std::vector<uint32_t> idx;
  auto tri = [&](uint32_t a, uint32_t b, uint32_t c) {
    const Triangle t{v[a], v[b], v[c]};
    if (t.degenerate()) return;
    const Vec3 mid = (t.v0 + t.v1 + t.v2) / 3.f;
    if (glm::dot(t.normal(), mid - centre) < 0) std::swap(b, c);  // wind outwards
    idx.insert(idx.end(), {a, b, c});
  };
  for (int i = 0; i < stacks; ++i)
    for (int k = 0; k < slices; ++k) {
      const uint32_t a = i * (slices + 1) + k, b = a + 1, c = a + slices + 1, d = c + 1;
      tri(a, c, b);
      tri(b, c, d);
    }
  return mesh(name, v, idx, material);
}

uint32_t SceneBuilder::box(const std::string& name, Vec3 lo, Vec3 hi, int material) {
  std::vector<Vec3> v;
  for (int i = 0; i < 8; ++i)
    v.push_back(Vec3(i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z));
  const Vec3 centre = (lo + hi) * 0.5f;
  std::vector<uint32_t> idx;
  const int faces[6][4] = {{0, 2, 6, 4}, {1, 3, 7, 5}, {0, 1, 5, 4},
                           {2, 3, 7, 6}, {0, 1, 3, 2}, {4, 5, 7, 6}};
  for (const auto& f : faces)
    for (auto [a, b, c] : {std::tuple{f[0], f[1], f[2]}, std::tuple{f[0], f[2], f[3]}}) {
      const Triangle t{v[a], v[b], v[c]};
      const bool out = glm::dot(t.normal(), (t.v0 + t.v1 + t.v2) / 3.f - centre) > 0;
      idx.insert(idx.end(), {uint32_t(a), uint32_t(out ? b : c), uint32_t(out ? c : b)});
    }
  return mesh(name, v, idx, material);
}

void SceneBuilder::point_light(const std::string& name, Vec3 pos, float intensity) {
  auto& lights = j_["extensions"]["KHR_lights_punctual"]["lights"];
  lights.push_back(
      {{"type", "point"}, {"name", name}, {"intensity", intensity}, {"color", {1.0, 1.0, 1.0}}});
  j_["nodes"].push_back(
      {{"name", name},
       {"translation", {pos.x, pos.y, pos.z}},
       {"extensions", {{"KHR_lights_punctual", {{"light", lights.size() - 1}}}}}});
  j_["scenes"][0]["nodes"].push_back(j_["nodes"].size() - 1);
}

void SceneBuilder::camera(Vec3 eye, Vec3 target, Vec3 up, float fov_y_deg, int width, int height) {
  camera_ = {{"eye", {eye.x, eye.y, eye.z}},     {"target", {target.x, target.y, target.z}},
             {"up", {up.x, up.y, up.z}},         {"fov_y_deg", fov_y_deg},
             {"aspect", double(width) / height}, {"image_size", {width, height}}};
}

std::string SceneBuilder::write(const std::string& dir, const std::string& name) const {
  nlohmann::json j = j_;
  j["buffers"] = {{{"byteLength", bin_.size()}, {"uri", name + ".bin"}}};
  std::ofstream(dir + "/" + name + ".bin", std::ios::binary)
      .write(reinterpret_cast<const char*>(bin_.data()), static_cast<std::streamsize>(bin_.size()));
  std::ofstream(dir + "/" + name + ".camera.json") << camera_.dump(2);
  const std::string path = dir + "/" + name + ".gltf";
  std::ofstream(path) << j.dump(2);
  return path;
}

}  // namespace hrpp::test
