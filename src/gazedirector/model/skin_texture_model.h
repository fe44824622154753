#pragma once

#include <array>
#include <filesystem>
#include <string>
#include <vector>

#include "gazedirector/render/texture.h"

namespace gazedirector {

// The linear texture model of the facial eye region (the paper's M_tex):
// texture(τ) = mean + Σ_j τ_j σ_j v_j, with τ in standard deviations, built by
// PCA from the 20 scanned skin maps masked to the mesh's uv footprint. Each
// map comes with a look-down variant (the upper lid unfolded); both variants
// share the coefficients, so one τ gives both textures.
class SkinTextureModel {
 public:
  static constexpr int kSize = 256;  // texels per side; ample for eyes up to ~250 px wide
  enum Variant { kAhead = 0, kLookDown = 1 };

  // Reads the PCA from the cache folder, building and caching it from
  // `skin_dir` (about 3 s) when absent or stale. The cache is optional: an
  // unwritable cache folder only costs the rebuild next time.
  static SkinTextureModel LoadOrBuild(const std::filesystem::path& skin_dir, const std::filesystem::path& cache_dir,
                                      int num_modes);
  static SkinTextureModel Build(const std::filesystem::path& skin_dir, int num_modes);

  int num_modes() const { return static_cast<int>(stddev_.size()); }
  int num_subjects() const { return static_cast<int>(subject_names_.size()); }
  const std::vector<std::string>& subject_names() const { return subject_names_; }
  double stddev(int mode) const { return stddev_[mode]; }
  // size*size*3 floats, RGB, rows from the top (v = 1).
  const float* mean(Variant variant) const { return mean_[variant].data(); }
  // Mode j already multiplied by its standard deviation: one unit of τ_j.
  const float* mode(int j, Variant variant) const { return modes_[j][variant].data(); }
  // The texture of subject i's coefficients (for tests of the PCA).
  const std::vector<double>& subject_coefficients(int subject) const { return coefficients_[subject]; }
  // 1 inside the mesh's uv footprint.
  const std::vector<float>& footprint() const { return footprint_; }

  // Writes mean + Σ τ_j mode_j into both textures (RGB, the fourth channel
  // 0) and builds their mips.
  void Compose(const double* tau, RgbaTexture& ahead, RgbaTexture& look_down) const;

  // Reads a skin map as a size x size float RGB texture, the eye hole filled.
  static std::vector<float> LoadSkinMap(const std::filesystem::path& path, int size);

 private:
  void Save(const std::filesystem::path& path, const std::string& fingerprint) const;
  static bool TryLoad(const std::filesystem::path& path, const std::string& fingerprint, int num_modes,
                      SkinTextureModel& model);

  std::vector<std::string> subject_names_;
  std::vector<float> mean_[2];
  std::vector<std::array<std::vector<float>, 2>> modes_;
  std::vector<double> stddev_;
  std::vector<std::vector<double>> coefficients_;
  std::vector<float> footprint_;
};

}  // namespace gazedirector
