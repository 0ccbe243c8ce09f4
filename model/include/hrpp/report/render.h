// Pictures of a scene and of the predictor's work on it (docs/workloads.md, "Pictures"): a
// direct-lighting image that shows the camera, lights and geometry are right, and per-pixel heat
// maps of the cost model's net cycles, the baseline walk's work and the predictor's outcomes.
// Every picture has a legend band under it that names its scene, workload, predictor
// configuration and units.
#pragma once

#include <cstdint>
#include <functional>
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
/// S split at spaces into lines at most MAX_WIDTH pixels wide at SCALE (a longer word is cut).
std::vector<std::string> wrap_text(const std::string& s, int max_width, int scale = 1);

/// How many display pixels a picture of W x H pixels draws each of its pixels with: small
/// pictures are enlarged (nearest neighbour) to at least 256 pixels on their longer side.
int display_scale(int w, int h);
/// IMG with every pixel drawn as a K x K square.
Image upscale(const Image& img, int k);

/// The text band under a picture: lines above an optional colour bar (the title), the bar with
/// its labels, lines under it (units, statistics), and the run's caption (scene, workload,
/// predictor), dimmer. The band is at least 480 pixels wide (960 with the text at scale 2, for
/// pictures 640 or more pixels wide) whatever the picture's size, and as tall as its text needs.
struct HeatMap;
struct Legend {
  std::vector<std::string> head{};
  const HeatMap* bar = nullptr;
  std::vector<std::string> body{};
  std::vector<std::string> caption{};
};
/// Where with_legend put the picture: its top-left corner and the text scale.
struct LegendLayout {
  int x0 = 0, text_scale = 1, band_y = 0;
};
/// PICTURE (already at its display size) centred above its legend band.
Image with_legend(const Image& picture, const Legend& legend, LegendLayout* layout = nullptr);

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
/// PROGRESS (optional) is told the pixels done after each row.
using RowProgress = std::function<void(uint64_t done, uint64_t total)>;
Image shade(const Scene& scene, const Bvh& bvh, const WorkloadOptions& opt, ShadeInfo* info,
            const RowProgress& progress = nullptr);

/// Per-pixel sums over every ray of the workload (all kinds) run through the predictor.
struct PixelStats {
  int width = 0, height = 0, spp = 1;
  std::vector<uint64_t> baseline_interior, hrpp_interior;  // interior-node tests
  std::vector<uint32_t> rays, failed;  // rays; rays whose prediction failed (false positives)
  // Cost-model cycles (hrpp/timing/cost_model.h, cycle_cost of each ray alone): the baseline
  // walks', and HRPP's (lookup, decision, predicted and full walks, mispredict penalties).
  std::vector<double> baseline_cycles, hrpp_cycles;
};
/// Runs the workload through `pred` and accumulates per pixel; PROGRESS (optional) is told the
/// camera samples done every 256 of them.
PixelStats predictor_pixels(const Scene& scene, const Bvh& bvh, const WorkloadOptions& opt,
                            Predictor* pred, const RowProgress& progress = nullptr);

/// One heat map: values per pixel (NaN: no data, drawn grey), a colour map, and a legend band
/// under the image with the title, the colour bar with its end values (and 0 inside a diverging
/// bar), its units, min / mean / max, and the caption naming the run.
struct HeatMap {
  std::string title{};
  std::string colormap = "viridis";   // "viridis" (sequential) or "coolwarm" (diverging)
  double lo = 0, hi = 1;              // colour bar range (values outside are clamped)
  bool percent = false;               // labels as percentages
  std::string units{};                // what the values count, e.g. "net cycles saved per pixel"
  std::string lo_note{}, hi_note{};   // after the end labels, e.g. "HRPP costs", "HRPP saves"
  std::string meaning{};              // one sentence for render.json
  double min = 0, mean = 0, max = 0;  // of the values with data (filled by heat_map_image)
  nlohmann::json to_json() const;
};
/// Maps t in [0, 1] through a colour map (display values).
Vec3 colormap(const std::string& name, double t);
/// The heat map at its display scale above its legend band; CAPTION names the run.
Image heat_map_image(const std::vector<double>& values, int width, int height, HeatMap* map,
                     const std::vector<std::string>& caption = {}, LegendLayout* layout = nullptr);

/// A short line naming a predictor configuration, for captions when the caller gives none:
/// "hash improved, table 128x8 (K=2), go-up 0, mode closest-exact".
std::string config_caption(const PredictorConfig& cfg);

struct RenderOptions {
  nlohmann::json tool{};  // when not null, leads render.json as its "tool" object
  std::string config{};   // the predictor configuration as the captions name it (empty: cfg's)
  /// Told the phase ("shading", then "predictor"), its unit, and how many are done of how many.
  std::function<void(const char* phase, const char* unit, uint64_t done, uint64_t total)>
      progress{};
};

struct RenderOutput {
  std::vector<std::string> files;
  nlohmann::json summary;  // also written to DIR/render.json
};
/// Writes DIR/shaded.png, net_cycles.png, work.png, skipped.png, mispredicted.png and
/// render.json (the figures behind every legend, each picture's meaning and units, the net
/// cycle totals). DIR must exist. Throws RenderError on a write failure.
RenderOutput render_all(const Scene& scene, const Bvh& bvh, const WorkloadOptions& opt,
                        const PredictorConfig& cfg, const std::string& dir,
                        const RenderOptions& ro = {});

}  // namespace hrpp
