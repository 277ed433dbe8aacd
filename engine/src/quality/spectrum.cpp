// quality/spectrum.cpp — the frequency domain: aliasing energy and spectrum images (FFTW).
//
// Takes: an Image. Gives: aliasing_energy() and spectrum_image() as mosaic/quality.hpp defines
// them. Transforms are real-to-complex 2-D DFTs in double (fftw_plan_dft_r2c_2d); the
// spectrum's other half follows from Hermitian symmetry, X(-f) = conj(X(f)).
#include <fftw3.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <memory>
#include <vector>

#include "mosaic/errors.hpp"
#include "quality/quality.hpp"

namespace mosaic::quality {
namespace {

/// Rec. 709 luma weights (on the stored values; the metric compares images, not light).
constexpr double kLumaR = 0.2126, kLumaG = 0.7152, kLumaB = 0.0722;
/// Added to a power before its logarithm so an exact zero maps to the floor, not -infinity.
constexpr double kTinyPower = 1e-30;

/// An unnormalised 2-D DFT of a height × width real image: rows of width / 2 + 1 bins.
class Dft {
 public:
  Dft(int width, int height) : w_(width), h_(height) {
    const std::size_t n = static_cast<std::size_t>(width) * height;
    in_.reset(fftw_alloc_real(n));
    out_.reset(fftw_alloc_complex(static_cast<std::size_t>(height) * (width / 2 + 1)));
    if (!in_ || !out_) throw Error(Errc::kInvalidArgument, "quality: FFT buffers");
    plan_ = fftw_plan_dft_r2c_2d(height, width, in_.get(), out_.get(), FFTW_ESTIMATE);
  }
  ~Dft() { fftw_destroy_plan(plan_); }
  Dft(const Dft&) = delete;
  Dft& operator=(const Dft&) = delete;

  double* input() { return in_.get(); }
  void run() { fftw_execute(plan_); }
  /// X(kx, ky) for 0 <= kx < width, 0 <= ky < height.
  std::complex<double> at(int kx, int ky) const {
    if (kx <= w_ / 2) {
      const fftw_complex& c = out_.get()[static_cast<std::size_t>(ky) * (w_ / 2 + 1) + kx];
      return {c[0], c[1]};
    }
    const int mx = w_ - kx, my = (h_ - ky) % h_;
    const fftw_complex& c = out_.get()[static_cast<std::size_t>(my) * (w_ / 2 + 1) + mx];
    return {c[0], -c[1]};
  }
  /// Sum of |X|² over every frequency except zero, over the full (two-sided) spectrum.
  double energy_without_dc() const {
    double e = 0;
    for (int ky = 0; ky < h_; ++ky) {
      for (int kx = 0; kx <= w_ / 2; ++kx) {
        if (kx == 0 && ky == 0) continue;
        const fftw_complex& c = out_.get()[static_cast<std::size_t>(ky) * (w_ / 2 + 1) + kx];
        // Columns 1 .. ceil(w/2) - 1 stand for themselves and their mirror image.
        const bool mirrored = kx != 0 && !(w_ % 2 == 0 && kx == w_ / 2);
        e += (mirrored ? 2.0 : 1.0) * (c[0] * c[0] + c[1] * c[1]);
      }
    }
    return e;
  }

 private:
  struct RealFree {
    void operator()(double* p) const { fftw_free(p); }
  };
  struct ComplexFree {
    void operator()(fftw_complex* p) const { fftw_free(p); }
  };
  int w_, h_;
  std::unique_ptr<double, RealFree> in_;
  std::unique_ptr<fftw_complex, ComplexFree> out_;
  fftw_plan plan_ = nullptr;
};

std::vector<double> luma(const Image& img) {
  if (img.width < 1 || img.height < 1 ||
      img.rgb.size() != static_cast<std::size_t>(img.width) * img.height * 3) {
    throw Error(Errc::kInvalidArgument, "quality: empty or malformed image");
  }
  std::vector<double> l(static_cast<std::size_t>(img.width) * img.height);
  for (std::size_t i = 0; i < l.size(); ++i)
    l[i] = kLumaR * img.rgb[3 * i] + kLumaG * img.rgb[3 * i + 1] + kLumaB * img.rgb[3 * i + 2];
  return l;
}

}  // namespace

double aliasing_energy(const Image& image, const Annulus& window) {
  const std::vector<double> l = luma(image);
  const int w = image.width, h = image.height;
  std::vector<char> in(l.size(), 0);
  double sum = 0, count = 0;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const double r = std::hypot(x + 0.5 - window.cx, y + 0.5 - window.cy);
      const std::size_t i = static_cast<std::size_t>(y) * w + x;
      if (r >= window.r_in && r <= window.r_out) {
        in[i] = 1;
        sum += l[i];
        count += 1;
      }
    }
  }
  if (count == 0) throw Error(Errc::kInvalidArgument, "quality: empty aliasing window");
  const double mean = sum / count;
  Dft dft(w, h);
  for (std::size_t i = 0; i < l.size(); ++i) dft.input()[i] = in[i] ? l[i] - mean : 0.0;
  dft.run();
  return dft.energy_without_dc() / (static_cast<double>(l.size()) * count);
}

std::vector<Rgba8> spectrum_image(const Image& image) {
  const std::vector<double> l = luma(image);
  const int w = image.width, h = image.height;
  double mean = 0;
  for (double v : l) mean += v;
  mean /= static_cast<double>(l.size());
  Dft dft(w, h);
  for (std::size_t i = 0; i < l.size(); ++i) dft.input()[i] = l[i] - mean;
  dft.run();
  const double n2 = static_cast<double>(l.size()) * static_cast<double>(l.size());
  std::vector<Rgba8> out(l.size());
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      // Pixel (w/2, h/2) shows frequency zero.
      const int kx = ((x - w / 2) % w + w) % w, ky = ((y - h / 2) % h + h) % h;
      const double db = 10.0 * std::log10(std::norm(dft.at(kx, ky)) / n2 + kTinyPower);
      const double t =
          std::clamp((db - kSpectrumFloorDb) / (kSpectrumCeilDb - kSpectrumFloorDb), 0.0, 1.0);
      const auto g = static_cast<std::uint8_t>(std::lround(t * 255.0));
      out[static_cast<std::size_t>(y) * w + x] = {g, g, g, 255};
    }
  }
  return out;
}

}  // namespace mosaic::quality
