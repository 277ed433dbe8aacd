// cli/report_command.cpp — `mosaic report`: speed against error for every antialiasing mode.
//
// Takes: an output folder and sizes. Gives, in that folder: report.md (a table per scene: mode,
// ms per frame, RMS and max error, PSNR, aliasing energy), <scene>-pareto.svg (time against RMS
// error, log-log, Pareto front marked), <scene>-crops.png (nearest-neighbour magnified crops of
// 1x, 4x, 16x, FXAA on 1x and the ground truth, side by side) for the star and the zone plate,
// zoneplate-spectrum-<mode>.png, and texture-<filter>.png with texture-spectrum-<filter>.png
// for the textured floor. Times are medians of --frames frames at --size through the
// Renderer; errors are measured on the same scenes built at --error-size, where the exact
// ground truth is affordable (quality/quality.hpp).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iomanip>
#include <iostream>
#include <limits>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "cli_common.hpp"
#include "mosaic/mosaic.hpp"
#include "mosaic/post.hpp"
#include "quality/quality.hpp"

namespace mosaic::cli {
namespace {

/// Nearest-neighbour magnification of the crops, and their edge in pixels of the error render:
/// 48 px × 6 = 288 px panels, large enough to see single pixels, small enough for a README.
constexpr int kCropMagnify = 6;
constexpr int kCropSize = 48;
/// Grey gap between panels, in output pixels.
constexpr int kCropGap = 4;
/// Aliasing window of the zone plate: from just past the Nyquist radius (5 % margin so that the
/// ring at exactly Nyquist, which the box itself attenuates only partly, is left out) to just
/// inside the outer edge (2 % so that the plate's rim, a real edge, stays out).
constexpr double kZoneWindowIn = 1.05, kZoneWindowOut = 0.98;
/// The star's 72 wedges are 36 cycles per turn: local frequency 36 / (2 pi r) exceeds Nyquist
/// inside r = 36 / pi px; the window stops at 90 % of that radius.
constexpr double kStarCycles = 36.0;
constexpr double kStarWindowOut = 0.9;
constexpr double kPi = 3.14159265358979323846;
/// Largest --frames: a report, not a benchmark.
constexpr int kMaxFrames = 100;
/// SVG plot geometry, px.
constexpr int kSvgWidth = 720, kSvgHeight = 480, kSvgMargin = 70;

enum class PostPass { kNone, kFxaa, kTent, kGaussian };

struct Mode {
  std::string name;
  int samples = 1;
  bool ssaa = false;
  PostPass post = PostPass::kNone;
};

/// Every mode on the curve. SSAA at 1 sample is 1x MSAA (one shade per pixel either way), so it
/// appears once.
std::vector<Mode> modes() {
  return {{"1x", 1, false, PostPass::kNone},
          {"4x MSAA", 4, false, PostPass::kNone},
          {"8x MSAA", 8, false, PostPass::kNone},
          {"16x MSAA", 16, false, PostPass::kNone},
          {"4x SSAA", 4, true, PostPass::kNone},
          {"8x SSAA", 8, true, PostPass::kNone},
          {"16x SSAA", 16, true, PostPass::kNone},
          {"FXAA on 1x", 1, false, PostPass::kFxaa},
          {"FXAA on 4x", 4, false, PostPass::kFxaa},
          {"4x tent", 4, false, PostPass::kTent},
          {"4x Gaussian", 4, false, PostPass::kGaussian},
          {"16x tent", 16, false, PostPass::kTent},
          {"16x Gaussian", 16, false, PostPass::kGaussian}};
}

struct ReportOptions {
  std::string out;
  std::string size = "1920x1080";
  std::string error_size = "640x360";
  int frames = 5;
  int threads = 0;
};

/// A target for `mode` at the scene's size (per-sample colour kept only for the filter resolves).
RenderTarget make_target(const Mode& mode, const Scene& scene) {
  TargetOptions topt;
  topt.keep_sample_color = mode.post == PostPass::kTent || mode.post == PostPass::kGaussian;
  RenderTarget target(scene.width, scene.height, mode.samples, topt);
  target.set_clear(scene.clear_color, scene.clear_depth);
  return target;
}

/// Renders one frame of `scene` in `mode` into `target` (from make_target()) and writes the
/// final RGBA8 image, post pass included, into `out` (resized to the image).
void run_mode(const Mode& mode, const Scene& scene, Renderer& renderer, RenderTarget& target,
              std::vector<Rgba8>& out) {
  const std::vector<Draw> draws = scene.draws();
  renderer.render(Frame{draws, mode.ssaa, false}, target);
  out.assign(target.color().begin(), target.color().end());
  switch (mode.post) {
    case PostPass::kNone:
      break;
    case PostPass::kFxaa:
      post::fxaa(target.color(), scene.width, scene.height, out);
      break;
    case PostPass::kTent:
      post::filter_resolve(target, post::Filter::kTent, out);
      break;
    case PostPass::kGaussian:
      post::filter_resolve(target, post::Filter::kGaussian, out);
      break;
  }
}

/// The final image of one frame of `scene` in `mode`.
std::vector<Rgba8> mode_image(const Mode& mode, const Scene& scene, Renderer& renderer) {
  RenderTarget target = make_target(mode, scene);
  std::vector<Rgba8> out;
  run_mode(mode, scene, renderer, target, out);
  return out;
}

/// Median wall time of `frames` runs of the mode, render and post pass together, in ms. The
/// target and the output image are made once, as an application rendering frame after frame
/// would keep them: the time is the frame's, not the allocation's (first-touching a fresh
/// 1080p target costs more than rendering the star).
double median_ms(const Mode& mode, const Scene& scene, Renderer& renderer, int frames) {
  RenderTarget target = make_target(mode, scene);
  std::vector<Rgba8> out;
  std::vector<double> ms;
  run_mode(mode, scene, renderer, target, out);  // warm-up: first touch of target and arenas
  for (int i = 0; i < frames; ++i) {
    const auto t0 = std::chrono::steady_clock::now();
    run_mode(mode, scene, renderer, target, out);
    const auto t1 = std::chrono::steady_clock::now();
    ms.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
  }
  std::sort(ms.begin(), ms.end());
  return ms[ms.size() / 2];
}

struct Row {
  std::string mode;
  double ms = 0;
  quality::ErrorStats err;
  std::optional<double> alias;
};

struct QualityScene {
  std::string name, title;
  std::function<Scene(int, int)> make;
  bool exact = true;  // exact area ground truth; otherwise 64×64 supersampled
  std::function<std::optional<quality::Annulus>(int, int)> window;
};

std::string fixed(double v, int digits) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(digits) << v;
  return s.str();
}

std::string sci(double v) {
  std::ostringstream s;
  s << std::scientific << std::setprecision(2) << v;
  return s.str();
}

/// Rows on the Pareto front of (time, RMS error): no other row is at least as fast and at
/// least as accurate, and strictly better in one.
std::vector<bool> pareto(const std::vector<Row>& rows) {
  std::vector<bool> front(rows.size(), true);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    for (std::size_t j = 0; j < rows.size(); ++j) {
      const bool no_worse = rows[j].ms <= rows[i].ms && rows[j].err.rms <= rows[i].err.rms;
      const bool better = rows[j].ms < rows[i].ms || rows[j].err.rms < rows[i].err.rms;
      if (j != i && no_worse && better) front[i] = false;
    }
  }
  return front;
}

std::string xml_escape(const std::string& s) {
  std::string o;
  for (char c : s) {
    if (c == '<')
      o += "&lt;";
    else if (c == '>')
      o += "&gt;";
    else if (c == '&')
      o += "&amp;";
    else
      o += c;
  }
  return o;
}

/// The log-log plot of time against RMS error as SVG text.
std::string pareto_svg(const std::string& title, const std::vector<Row>& rows) {
  const std::vector<bool> front = pareto(rows);
  double tmin = std::numeric_limits<double>::max(), tmax = 0;
  double emin = std::numeric_limits<double>::max(), emax = 0;
  for (const Row& r : rows) {
    tmin = std::min(tmin, r.ms);
    tmax = std::max(tmax, r.ms);
    emin = std::min(emin, r.err.rms);
    emax = std::max(emax, r.err.rms);
  }
  // Whole decades around the data, so that the grid lines fall on 1, 10, 100 …
  const double lx0 = std::floor(std::log10(std::max(tmin, 1e-3)));
  const double lx1 = std::max(lx0 + 1, std::ceil(std::log10(std::max(tmax, 1e-3))));
  const double ly0 = std::floor(std::log10(std::max(emin, 1e-6)));
  const double ly1 = std::max(ly0 + 1, std::ceil(std::log10(std::max(emax, 1e-6))));
  const double pw = kSvgWidth - 2.0 * kSvgMargin, ph = kSvgHeight - 2.0 * kSvgMargin;
  auto X = [&](double ms) {
    return kSvgMargin + pw * (std::log10(std::max(ms, 1e-3)) - lx0) / (lx1 - lx0);
  };
  auto Y = [&](double e) {
    return kSvgMargin + ph * (1.0 - (std::log10(std::max(e, 1e-6)) - ly0) / (ly1 - ly0));
  };
  std::ostringstream s;
  s << std::fixed << std::setprecision(1);
  s << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << kSvgWidth << "\" height=\""
    << kSvgHeight << "\" font-family=\"sans-serif\" font-size=\"12\">\n";
  s << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  s << "<text x=\"" << kSvgWidth / 2 << "\" y=\"24\" text-anchor=\"middle\" font-size=\"15\">"
    << xml_escape(title) << ": time against RMS error (log-log)</text>\n";
  // Grid: decades and the 2 and 5 in between.
  for (double d = lx0; d <= lx1; d += 1) {
    for (double m : {1.0, 2.0, 5.0}) {
      const double v = m * std::pow(10.0, d);
      if (std::log10(v) > lx1 + 1e-9) break;
      const double x = X(v);
      s << "<line x1=\"" << x << "\" y1=\"" << kSvgMargin << "\" x2=\"" << x << "\" y2=\""
        << kSvgMargin + ph << "\" stroke=\"" << (m == 1.0 ? "#bbb" : "#eee") << "\"/>\n";
      s << "<text x=\"" << x << "\" y=\"" << kSvgMargin + ph + 16 << "\" text-anchor=\"middle\">"
        << v << "</text>\n";
    }
  }
  for (double d = ly0; d <= ly1; d += 1) {
    for (double m : {1.0, 2.0, 5.0}) {
      const double v = m * std::pow(10.0, d);
      if (std::log10(v) > ly1 + 1e-9) break;
      const double y = Y(v);
      s << "<line x1=\"" << kSvgMargin << "\" y1=\"" << y << "\" x2=\"" << kSvgMargin + pw
        << "\" y2=\"" << y << "\" stroke=\"" << (m == 1.0 ? "#bbb" : "#eee") << "\"/>\n";
      s << "<text x=\"" << kSvgMargin - 6 << "\" y=\"" << y + 4 << "\" text-anchor=\"end\">"
        << std::setprecision(static_cast<int>(std::max(0.0, -d))) << v << std::setprecision(1)
        << "</text>\n";
    }
  }
  s << "<rect x=\"" << kSvgMargin << "\" y=\"" << kSvgMargin << "\" width=\"" << pw
    << "\" height=\"" << ph << "\" fill=\"none\" stroke=\"black\"/>\n";
  s << "<text x=\"" << kSvgWidth / 2 << "\" y=\"" << kSvgHeight - 20
    << "\" text-anchor=\"middle\">ms per frame (median)</text>\n";
  s << "<text x=\"18\" y=\"" << kSvgHeight / 2
    << "\" text-anchor=\"middle\" transform=\"rotate(-90 18 " << kSvgHeight / 2
    << ")\">RMS error (1 = full colour range)</text>\n";
  // The front as a staircase polyline, fastest first.
  std::vector<const Row*> f;
  for (std::size_t i = 0; i < rows.size(); ++i)
    if (front[i]) f.push_back(&rows[i]);
  std::sort(f.begin(), f.end(), [](const Row* a, const Row* b) { return a->ms < b->ms; });
  s << "<polyline fill=\"none\" stroke=\"#d33\" stroke-width=\"2\" points=\"";
  for (std::size_t i = 0; i < f.size(); ++i) {
    if (i > 0) s << X(f[i]->ms) << "," << Y(f[i - 1]->err.rms) << " ";
    s << X(f[i]->ms) << "," << Y(f[i]->err.rms) << " ";
  }
  s << "\"/>\n";
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const double x = X(rows[i].ms), y = Y(rows[i].err.rms);
    s << "<circle cx=\"" << x << "\" cy=\"" << y << "\" r=\"4\" fill=\""
      << (front[i] ? "#d33" : "#36c") << "\"/>\n";
    s << "<text x=\"" << x + 6 << "\" y=\"" << y - 6 << "\" font-size=\"10\">"
      << xml_escape(rows[i].mode) << "</text>\n";
  }
  s << "<text x=\"" << kSvgMargin + pw - 4 << "\" y=\"" << kSvgMargin + 14
    << "\" text-anchor=\"end\" fill=\"#d33\">red: Pareto front</text>\n";
  s << "</svg>\n";
  return s.str();
}

/// Panels side by side, each the crop of a full image magnified by nearest neighbour.
void write_crops(const std::filesystem::path& path, const std::vector<std::vector<Rgba8>>& images,
                 int width, const quality::Rect& crop) {
  const int panel = crop.width * kCropMagnify;
  const int ph = crop.height * kCropMagnify;
  const int n = static_cast<int>(images.size());
  const int w = n * panel + (n - 1) * kCropGap;
  std::vector<Rgba8> out(static_cast<std::size_t>(w) * ph, Rgba8{96, 96, 96, 255});
  for (int i = 0; i < n; ++i) {
    for (int y = 0; y < ph; ++y) {
      for (int x = 0; x < panel; ++x) {
        const int sx = crop.x + x / kCropMagnify, sy = crop.y + y / kCropMagnify;
        out[static_cast<std::size_t>(y) * w + i * (panel + kCropGap) + x] =
            images[static_cast<std::size_t>(i)][static_cast<std::size_t>(sy) * width + sx];
      }
    }
  }
  quality::write_png(path, out, w, ph);
}

/// Median wall time of `frames` renders of the textured floor with `sampler` at `size`, in ms
/// (one target, warmed up first, as median_ms()).
double texture_ms(const Sampler& sampler, Size size, int frames, Renderer& renderer) {
  RenderTarget target(size.width, size.height, 1);
  quality::render_textured_plane(sampler, target, renderer);
  std::vector<double> ms;
  for (int i = 0; i < frames; ++i) {
    const auto t0 = std::chrono::steady_clock::now();
    quality::render_textured_plane(sampler, target, renderer);
    ms.push_back(
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
  }
  std::sort(ms.begin(), ms.end());
  return ms[ms.size() / 2];
}

/// Texture aliasing: the checkerboard floor with each filter, its error against the
/// supersampled ground truth, its time, and its spectrum.
void texture_section(std::ostringstream& md, const std::filesystem::path& dir, Size size,
                     Size esize, int frames, Renderer& renderer) {
  std::cerr << "report: textured floor" << std::endl;
  struct Filter {
    const char* name;
    const char* stem;
    Sampler sampler;
  };
  const Filter filters[] = {
      {"nearest, no mipmaps", "nearest", Sampler::nearest()},
      {"bilinear, no mipmaps", "bilinear", Sampler::bilinear()},
      {"bilinear, nearest mip level", "bilinear-mip", Sampler::bilinear_mip()},
      {"trilinear", "trilinear", Sampler::trilinear()}};
  const quality::Rect full{0, 0, esize.width, esize.height};
  const quality::Image truth = quality::textured_plane_truth(esize.width, esize.height, renderer);
  md << "## Texture aliasing (checkerboard floor at a grazing angle)\n\n";
  md << "A " << quality::kTexturePlaneSize << "x" << quality::kTexturePlaneSize
     << " black-and-white checkerboard of 8-texel cells, repeated over a floor that runs from "
        "under the camera to the distance, one sample per pixel (MSAA does not filter inside a "
        "triangle). Ground truth: the same view rendered "
     << quality::kTextureTruthGrid << "x larger with point sampling, averaged per pixel ("
     << quality::kTextureTruthGrid * quality::kTextureTruthGrid << " samples). Errors at "
     << esize.width << "x" << esize.height << ", times at " << size.width << "x" << size.height
     << " (median of " << frames << ").\n\n";
  md << "| filter | ms/frame at " << size.width << "x" << size.height
     << " | RMS error | max error | PSNR (dB) |\n|---|---:|---:|---:|---:|\n";
  std::vector<std::pair<std::string, std::vector<Rgba8>>> spectra{
      {"ground-truth", quality::to_rgba8(truth)}};
  for (const Filter& f : filters) {
    const double ms = texture_ms(f.sampler, size, frames, renderer);
    RenderTarget target(esize.width, esize.height, 1);
    quality::render_textured_plane(f.sampler, target, renderer);
    const std::vector<Rgba8> img(target.color().begin(), target.color().end());
    const quality::ErrorStats e =
        quality::compare(truth, quality::to_image(img, esize.width, esize.height, full));
    md << "| " << f.name << " | " << fixed(ms, ms < 10 ? 2 : 1) << " | " << fixed(e.rms, 4) << " | "
       << fixed(e.max, 3) << " | " << fixed(e.psnr, 1) << " |\n";
    spectra.emplace_back(f.stem, img);
  }
  md << "\nImages and spectra (log power of the luma DFT, as for the zone plate): aliasing shows "
        "as a moiré in the distance and as energy folded back across the spectrum.\n\n|";
  for (const auto& [stem, img] : spectra) md << " " << stem << " |";
  md << "\n|";
  for (std::size_t i = 0; i < spectra.size(); ++i) md << "---|";
  md << "\n|";
  for (const auto& [stem, img] : spectra) {
    const std::string file = "texture-" + stem + ".png";
    quality::write_png(dir / file, img, esize.width, esize.height);
    md << " ![" << stem << "](" << file << ") |";
  }
  md << "\n|";
  for (const auto& [stem, img] : spectra) {
    const std::string file = "texture-spectrum-" + stem + ".png";
    quality::write_png(
        dir / file,
        quality::spectrum_image(quality::to_image(img, esize.width, esize.height, full)),
        esize.width, esize.height);
    md << " ![" << stem << " spectrum](" << file << ") |";
  }
  md << "\n\n";
}

int run_report(const ReportOptions& o) {
  const auto t_start = std::chrono::steady_clock::now();
  const std::optional<Size> size = parse_size(o.size);
  const std::optional<Size> esize = parse_size(o.error_size);
  if (!size || !esize) throw UsageError("report: sizes must be WxH");
  if (esize->width < kCropSize || esize->height < kCropSize)
    throw UsageError("report: --error-size must be at least 48x48 for the crops");
  const std::filesystem::path dir(o.out);
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw Error(Errc::kIo, "report: cannot create " + dir.string() + ": " + ec.message());

  RendererOptions ropt;
  ropt.threads = o.threads;
  Renderer renderer(ropt);

  const std::vector<QualityScene> scenes = {
      {"star", "Siemens star (built-in `star`, 72 wedges)",
       [](int w, int h) { return builtin_scene("star", w, h); }, true,
       [](int w, int h) -> std::optional<quality::Annulus> {
         return quality::Annulus{w / 2.0, h / 2.0, 0.0, kStarWindowOut * kStarCycles / kPi};
       }},
      {"zoneplate", "Zone plate of thin triangles (0 to 1 cycle/px)", quality::zone_plate_scene,
       true,
       [](int w, int h) -> std::optional<quality::Annulus> {
         const quality::ZonePlate z = quality::zone_plate_for(w, h);
         return quality::Annulus{z.cx, z.cy, kZoneWindowIn * z.nyquist_radius(),
                                 kZoneWindowOut * z.radius};
       }},
      {"mesh", "Watertight mesh (jittered grid, flat colours)",
       [](int w, int h) { return quality::mesh_scene(w, h); }, true,
       [](int, int) -> std::optional<quality::Annulus> { return std::nullopt; }},
      {"overlap", "Overlap and depth (interpenetrating triangles; 64x64 supersampled truth)",
       [](int w, int h) { return quality::overlap_scene(w, h); }, false,
       [](int, int) -> std::optional<quality::Annulus> { return std::nullopt; }},
  };

  std::ostringstream md;
  md << "# mosaic antialiasing report\n\n";
  md << "Command: `mosaic report --out " << o.out << " --size " << o.size << " --error-size "
     << o.error_size << " --frames " << o.frames << "`\n\n";
  md << "- Renderer: ISA " << to_string(renderer.isa()) << ", " << renderer.threads()
     << " worker threads.\n";
  md << "- **ms/frame**: median of " << o.frames << " frames at " << size->width << "x"
     << size->height << " through `Renderer::render`, plus the post pass where there is one "
     << "(FXAA, or the tent/Gaussian resolve from the kept per-sample colours, which also costs "
     << "writing them).\n";
  md << "- **Errors** are measured on the same scenes built at " << esize->width << "x"
     << esize->height << " (the exact ground truth at full size would take minutes), over every "
     << "pixel and RGB channel, in units of the full colour range (1 = 255): RMS, max, and "
     << "PSNR = 20 log10(1 / RMS).\n";
  md << "- **Ground truth**: the ideal box filter, i.e. the exact area of every triangle inside "
     << "every pixel, computed in rational arithmetic on the snapped 16.8 vertices; for the "
     << "overlap scene, a regular 64x64-sample supersampled render (error at most 127/4096 of "
     << "the colour step per boundary crossing a pixel).\n";
  md << "- **Aliasing energy**: the mean square luma, per window pixel, of the DFT (FFTW) of "
     << "the image inside a window where the scene has no content below Nyquist (zone plate: "
     << "radii from 1.05x the Nyquist radius to 0.98x the outer radius; star: the centre, "
     << "r < 0.9 * 36/pi px), mean removed. All of it is energy that sampling folded back below "
     << "Nyquist; the ground truth's own (box-filter) aliasing is the first row.\n";
  md << "- SSAA at 1 sample equals 1x; the 1x row stands for both. On flat-coloured scenes SSAA "
     << "and MSAA give the same image, so they differ only in time.\n\n";

  for (const QualityScene& qs : scenes) {
    std::cerr << "report: " << qs.name << std::endl;
    const Scene timing_scene = qs.make(size->width, size->height);
    const Scene error_scene = qs.make(esize->width, esize->height);
    const quality::Rect full{0, 0, esize->width, esize->height};
    const quality::Image truth = qs.exact
                                     ? quality::exact_box_image(error_scene, full)
                                     : quality::supersampled_image(error_scene, full, renderer);
    const std::optional<quality::Annulus> window = qs.window(esize->width, esize->height);
    std::vector<Row> rows;
    std::vector<std::vector<Rgba8>> images;
    for (const Mode& m : modes()) {
      Row r;
      r.mode = m.name;
      r.ms = median_ms(m, timing_scene, renderer, o.frames);
      images.push_back(mode_image(m, error_scene, renderer));
      const quality::Image img =
          quality::to_image(images.back(), esize->width, esize->height, full);
      r.err = quality::compare(truth, img);
      if (window) r.alias = quality::aliasing_energy(img, *window);
      rows.push_back(r);
    }
    const std::vector<bool> front = pareto(rows);
    md << "## " << qs.title << "\n\n";
    md << "![" << qs.name << " Pareto plot](" << qs.name << "-pareto.svg)\n\n";
    md << "| mode | ms/frame at " << size->width << "x" << size->height
       << " | RMS error | max error | PSNR (dB) | aliasing energy | Pareto |\n";
    md << "|---|---:|---:|---:|---:|---:|:-:|\n";
    if (window) {
      md << "| ground truth (box) | – | 0 | 0 | ∞ | "
         << sci(quality::aliasing_energy(truth, *window)) << " | |\n";
    }
    for (std::size_t i = 0; i < rows.size(); ++i) {
      const Row& r = rows[i];
      md << "| " << r.mode << " | " << fixed(r.ms, r.ms < 10 ? 2 : 1) << " | "
         << fixed(r.err.rms, 4) << " | " << fixed(r.err.max, 3) << " | " << fixed(r.err.psnr, 1)
         << " | " << (r.alias ? sci(*r.alias) : "–") << " | " << (front[i] ? "●" : "") << " |\n";
    }
    md << "\n";
    {
      std::ofstream svg(dir / (qs.name + "-pareto.svg"));
      svg << pareto_svg(qs.title, rows);
      if (!svg) throw Error(Errc::kIo, "report: cannot write the SVG plot");
    }
    if (qs.name == "star" || qs.name == "zoneplate") {
      // Star: just right of the centre, where wedges are a few pixels wide and jaggies show.
      // Zone plate: around 0.75 of the radius on the right, where the rings (0.75 cycle/px) are
      // beyond Nyquist and alias into moiré.
      const int cx = esize->width / 2, cy = esize->height / 2;
      const int r = std::min(esize->width, esize->height);
      const int ox = qs.name == "star" ? cx + r / 10 : cx + static_cast<int>(0.75 * 0.48 * r);
      quality::Rect crop{std::clamp(ox - kCropSize / 2, 0, esize->width - kCropSize),
                         std::clamp(cy - kCropSize / 2, 0, esize->height - kCropSize), kCropSize,
                         kCropSize};
      const std::vector<Rgba8> gt = quality::to_rgba8(truth);
      write_crops(dir / (qs.name + "-crops.png"), {images[0], images[1], images[3], images[7], gt},
                  esize->width, crop);
      md << "Crops (" << kCropSize << "x" << kCropSize << " px at (" << crop.x << ", " << crop.y
         << "), magnified " << kCropMagnify << "x, nearest neighbour), left to right: 1x, 4x MSAA, "
         << "16x MSAA, FXAA on 1x, ground truth:\n\n![" << qs.name << " crops](" << qs.name
         << "-crops.png)\n\n";
    }
    if (qs.name == "zoneplate") {
      md << "Spectra (log power of the luma DFT, zero frequency in the middle, "
         << quality::kSpectrumFloorDb << " dB black to " << quality::kSpectrumCeilDb
         << " dB white): the true chirp fills the disc out to Nyquist; aliasing shows as "
            "mirrored chirps.\n\n";
      md << "| ground truth | 1x | 4x MSAA | 16x MSAA | FXAA on 1x | 16x Gaussian "
            "|\n|---|---|---|---|---|---|\n|";
      const std::vector<std::pair<std::string, std::vector<Rgba8>>> spectra = {
          {"ground-truth", quality::to_rgba8(truth)},
          {"1x", images[0]},
          {"4x-msaa", images[1]},
          {"16x-msaa", images[3]},
          {"fxaa-on-1x", images[7]},
          {"16x-gaussian", images[12]}};
      for (const auto& [stem, img] : spectra) {
        const std::string file = "zoneplate-spectrum-" + stem + ".png";
        quality::write_png(
            dir / file,
            quality::spectrum_image(quality::to_image(img, esize->width, esize->height, full)),
            esize->width, esize->height);
        md << " ![" << stem << "](" << file << ") |";
      }
      md << "\n\n";
    }
  }
  texture_section(md, dir, *size, *esize, o.frames, renderer);
  const double total_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  md << "Report written in " << fixed(total_s, 1) << " s.\n";
  std::ofstream f(dir / "report.md");
  f << md.str();
  if (!f) throw Error(Errc::kIo, "report: cannot write report.md");
  std::cerr << "report: wrote " << printable((dir / "report.md").string()) << " in "
            << fixed(total_s, 1) << " s" << std::endl;
  return kExitOk;
}

}  // namespace

Command add_report_command(CLI::App& parent) {
  auto o = std::make_shared<ReportOptions>();
  CLI::App* app = parent.add_subcommand(
      "report", "Measure every antialiasing mode's time and error; write a report folder");
  app->add_option("--out", o->out, "Folder to write report.md, plots and images into")
      ->required()
      ->type_name("DIR");
  app->add_option("--size", o->size, "Size WxH the frames are timed at")
      ->type_name("WxH")
      ->check(size_validator())
      ->capture_default_str();
  app->add_option("--error-size", o->error_size,
                  "Size WxH the errors are measured at, against the exact ground truth")
      ->type_name("WxH")
      ->check(size_validator())
      ->capture_default_str();
  app->add_option("--frames", o->frames, "Frames timed per mode (the median is reported)")
      ->type_name("N")
      ->transform(integer_in(1, kMaxFrames))
      ->capture_default_str();
  app->add_option("--threads", o->threads, "Worker threads; 0 = every hardware thread")
      ->type_name("N")
      ->transform(thread_count(0))
      ->capture_default_str();
  return Command{app, [o] { return run_report(*o); }};
}

}  // namespace mosaic::cli
