#include "test_util.h"

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "hrpp/util/rng.h"

namespace hrpp::test {
namespace fs = std::filesystem;

std::string shared_scene(const std::string& file) {
  fs::path p = fs::path(HRPP_SHARED_DIR) / "scenes" / file;
  return fs::exists(p) ? p.string() : std::string();
}

static std::vector<std::string> glbs_in(const fs::path& dir) {
  std::vector<std::string> out;
  if (!fs::is_directory(dir)) return out;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().extension() == ".glb") out.push_back(e.path().string());
  std::sort(out.begin(), out.end());
  return out;
}

std::vector<std::string> shared_scenes() { return glbs_in(fs::path(HRPP_SHARED_DIR) / "scenes"); }
std::vector<std::string> own_scenes() { return glbs_in(fs::path(HRPP_SOURCE_DIR) / "scenes"); }

Scene scene_from_triangles(std::vector<Triangle> tris) {
  Scene s;
  s.path = "<memory>";
  s.name = "memory";
  s.materials.push_back(Material{.name = "matte", .metallic = 0.f});
  for (const Triangle& t : tris) {
    s.bounds.grow(t.bounds());
    if (t.degenerate()) s.degenerate_triangles++;
  }
  s.tri_material.assign(tris.size(), 0);
  s.meshes.push_back(MeshRange{"all", 0, static_cast<uint32_t>(tris.size()), 0});
  s.triangles = std::move(tris);
  s.camera = default_camera(s.bounds);
  return s;
}

std::vector<Triangle> random_soup(size_t n, float scale, uint64_t seed) {
  std::vector<Triangle> out(n);
  auto u = [&](uint64_t i, uint64_t k) { return 2.f * uniform01(seed, i, k) - 1.f; };
  for (size_t i = 0; i < n; ++i) {
    Vec3 c(u(i, 0), u(i, 1), u(i, 2));
    out[i].v0 = c + scale * Vec3(u(i, 3), u(i, 4), u(i, 5));
    out[i].v1 = c + scale * Vec3(u(i, 6), u(i, 7), u(i, 8));
    out[i].v2 = c + scale * Vec3(u(i, 9), u(i, 10), u(i, 11));
  }
  return out;
}

Ray random_ray(uint64_t seed, uint64_t i) {
  auto u = [&](uint64_t k) { return 2.f * uniform01(seed, i, k) - 1.f; };
  Ray r;
  r.org = 1.5f * Vec3(u(0), u(1), u(2));
  r.dir = glm::normalize(Vec3(u(3), u(4), u(5)) - 0.3f * r.org);
  if (i % 5 == 0) r.tfar = 0.5f + uniform01(seed, i, 6);
  if (i % 7 == 0) r.tnear = 0.2f * uniform01(seed, i, 7);
  return r;
}

std::string temp_dir(const std::string& name) {
  fs::path p = fs::temp_directory_path() / ("hrpp_test_" + std::to_string(::getpid())) / name;
  fs::remove_all(p);
  fs::create_directories(p);
  return p.string();
}

static std::string base64(const std::vector<uint8_t>& data) {
  static const char* tbl = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (size_t i = 0; i < data.size(); i += 3) {
    uint32_t v = data[i] << 16;
    if (i + 1 < data.size()) v |= data[i + 1] << 8;
    if (i + 2 < data.size()) v |= data[i + 2];
    out += tbl[(v >> 18) & 63];
    out += tbl[(v >> 12) & 63];
    out += i + 1 < data.size() ? tbl[(v >> 6) & 63] : '=';
    out += i + 2 < data.size() ? tbl[v & 63] : '=';
  }
  return out;
}

nlohmann::json minimal_gltf(const std::vector<float>& positions,
                            const std::vector<uint32_t>& indices) {
  std::vector<uint8_t> bytes(positions.size() * 4 + indices.size() * 4);
  std::memcpy(bytes.data(), positions.data(), positions.size() * 4);
  std::memcpy(bytes.data() + positions.size() * 4, indices.data(), indices.size() * 4);
  std::vector<float> lo(3, 1e30f), hi(3, -1e30f);
  for (size_t i = 0; i < positions.size(); ++i) {
    lo[i % 3] = std::min(lo[i % 3], positions[i]);
    hi[i % 3] = std::max(hi[i % 3], positions[i]);
  }
  nlohmann::json j;
  j["asset"] = {{"version", "2.0"}};
  j["scene"] = 0;
  j["scenes"] = {{{"nodes", {0}}}};
  j["nodes"] = {{{"mesh", 0}, {"name", "tri"}}};
  j["meshes"] = {
      {{"primitives",
        {{{"attributes", {{"POSITION", 0}}}, {"indices", 1}, {"mode", 4}, {"material", 0}}}}}};
  j["materials"] = {{{"name", "m"}, {"pbrMetallicRoughness", {{"metallicFactor", 0.0}}}}};
  j["buffers"] = {{{"byteLength", bytes.size()},
                   {"uri", "data:application/octet-stream;base64," + base64(bytes)}}};
  j["bufferViews"] = {
      {{"buffer", 0}, {"byteOffset", 0}, {"byteLength", positions.size() * 4}},
      {{"buffer", 0}, {"byteOffset", positions.size() * 4}, {"byteLength", indices.size() * 4}}};
  j["accessors"] = {
      {{"bufferView", 0},
       {"componentType", 5126},
       {"count", positions.size() / 3},
       {"type", "VEC3"},
       {"min", lo},
       {"max", hi}},
      {{"bufferView", 1}, {"componentType", 5125}, {"count", indices.size()}, {"type", "SCALAR"}}};
  return j;
}

void write_text(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
}

}  // namespace hrpp::test
