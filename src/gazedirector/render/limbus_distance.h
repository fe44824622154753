#pragma once

#include <opencv2/core.hpp>

#include "gazedirector/model/eye_region_model.h"
#include "gazedirector/render/renderer.h"

namespace gazedirector {

// The signed distance in pixels from each eyeball pixel of `buffers` to the
// edge of the rendered iris (the eyeball texture's, as refracted through the
// cornea; positive on the sclera), from the interpolated distance of `posed`'s
// texture coordinates from the iris's centre and its change per pixel. Other
// pixels, and eyeball pixels where that distance does not change, read
// +-kFarFromLimbus.
inline constexpr float kFarFromLimbus = 1e3f;
cv::Mat LimbusDistance(const RenderBuffers& buffers, const EyeRegionModel& model, const PosedModel& posed);

}  // namespace gazedirector
