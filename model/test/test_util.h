// Helpers shared by the golden-model tests.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "hrpp/scene/scene.h"
#include "hrpp/trace/ray.h"

namespace hrpp::test {

/// Path of a scene in ../shared/scenes, or "" when the shared folder is absent.
std::string shared_scene(const std::string& file);
/// All .glb files of ../shared/scenes (empty when absent).
std::vector<std::string> shared_scenes();
/// The project's own scenes in scenes/.
std::vector<std::string> own_scenes();

/// A scene made of the given triangles with one matte material and a default camera.
Scene scene_from_triangles(std::vector<Triangle> tris);

/// Random triangle soup: n triangles of size ~scale inside [-1, 1]^3, deterministic in seed.
std::vector<Triangle> random_soup(size_t n, float scale, uint64_t seed);

/// Ray i of seed: from a random origin in [-1.5, 1.5]^3 roughly towards the centre of the soups;
/// every 5th with a finite tfar in [0.5, 1.5), every 7th with tnear in [0, 0.2).
Ray random_ray(uint64_t seed, uint64_t i);

/// A fresh temporary directory for one test.
std::string temp_dir(const std::string& name);

/// A minimal valid glTF (JSON, buffer as a data URI): one node, one mesh, one primitive.
/// The returned JSON can be edited to make malformed variants.
nlohmann::json minimal_gltf(const std::vector<float>& positions,
                            const std::vector<uint32_t>& indices);

/// Writes text to a file (creating it).
void write_text(const std::string& path, const std::string& text);

}  // namespace hrpp::test
