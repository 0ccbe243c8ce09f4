// Pictures of a scene and of the predictor's work on it (docs/workloads.md, "Pictures"): a
// direct-lighting image that shows the camera, lights and geometry are right, and per-pixel heat
// maps of the baseline walk's work and of the predictor's outcomes, with a legend.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "hrpp/predictor/predictor.h"
#include "hrpp/scene/scene.h"
#include "hrpp/trace/bvh.h"
#include "hrpp/workload/workload.h"

namespace hrpp {

/// A PNG could not be written. The message names the file.
class RenderError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// 8-bit sRGB image, rows top to bottom.
struct Image {
  int width = 0, height = 0;
  std::vector<uint8_t> rgb;  // width * height * 3

  Image() = default;
  Image(int w, int h, Vec3 fill = Vec3(0));
  /// Sets a pixel from display values in [0, 1] (clamped, already sRGB-encoded).
  void set(int x, int y, const Vec3& c);
  Vec3 get(int x, int y) const;
  void fill_rect(int x0, int y0, int x1, int y1, const Vec3& c);  // [x0, x1) x [y0, y1)
  /// Draws text (ASCII, stb_easy_font glyphs) with its top-left corner at (x, y), scaled.
  void text(int x, int y, const std::string& s, const Vec3& c, int scale = 1);
};
/// Width in pixels of text drawn with Image::text at scale 1.
int text_width(const std::string& s);

/// Writes a PNG (stb_image_write). Throws RenderError naming the file.
void write_png(const std::string& path, const Image& img);

/// sRGB transfer function of a linear value in [0, 1].
float srgb_encode(float linear);

/// Direct lighting at the workload's resolution and samples per pixel: Lambert with the
/// material's base colour, every punctual light and one point per emissive mesh (exactly the
/// shadow rays the workload spawns from primary hits), emitters shown with their colour,
/// auto-exposed, a small ambient term so unlit geometry stays visible, sRGB-encoded.
struct ShadeInfo {
  double exposure = 0;      // display value per unit of linear radiance
  double lit_fraction = 0;  // share of surface samples that some light reaches unoccluded
  uint64_t samples = 0, surface_samples = 0, emitter_samples = 0, background_samples = 0;
  nlohmann::json to_json() const;
};
Image shade(const Scene& scene, const Bvh& bvh, const WorkloadOptions& opt, ShadeInfo* info);

/// Per-pixel sums over every ray of the workload (all kinds) run through the predictor.
struct PixelStats {
  int width = 0, height = 0, spp = 1;
  std::vector<uint64_t> baseline_interior, hrpp_interior;  // interior-node tests
  std::vector<uint32_t> rays, failed;  // rays; rays whose prediction failed (false positives)
};
/// Runs the workload through `pred` and accumulates per pixel.
PixelStats predictor_pixels(const Scene& scene, const Bvh& bvh, const WorkloadOptions& opt,
                            Predictor* pred);

/// One heat map: values per pixel (NaN: no data, drawn grey), a colour map, and a legend strip
/// under the image with the title, the colour bar, its end values, and min / mean / max.
struct HeatMap {
  std::string title;
  std::string colormap = "viridis";   // "viridis" (sequential) or "coolwarm" (diverging)
  double lo = 0, hi = 1;              // colour bar range (values outside are clamped)
  bool percent = false;               // labels as percentages
  double min = 0, mean = 0, max = 0;  // of the values with data (filled by heat_map_image)
  nlohmann::json to_json() const;
};
/// Maps t in [0, 1] through a colour map (display values).
Vec3 colormap(const std::string& name, double t);
Image heat_map_image(const std::vector<double>& values, int width, int height, HeatMap* map);

struct RenderOutput {
  std::vector<std::string> files;
  nlohmann::json summary;  // also written to DIR/render.json
};
/// Writes DIR/shaded.png, work.png, skipped.png, mispredicted.png and render.json (the figures
/// behind every legend). DIR must exist. Throws RenderError on a write failure. TOOL, when not
/// null, leads render.json as its "tool" object (where the run came from: the hrpp tool's).
RenderOutput render_all(const Scene& scene, const Bvh& bvh, const WorkloadOptions& opt,
                        const PredictorConfig& cfg, const std::string& dir,
                        const nlohmann::json& tool = nullptr);

}  // namespace hrpp
