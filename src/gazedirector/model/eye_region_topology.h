#pragma once

#include <array>

namespace gazedirector::topology {

// Index lists of the 229-vertex facial eye-region mesh (the subject's left
// eye), measured on the assets; see ../shared/docs/eye-model.md.

inline constexpr int kNumRegionVertices = 229;

// The interior lid margin, a closed loop: inner corner, upper lid, outer
// corner (131, the vertex furthest toward the outer side), lower lid.
inline constexpr std::array<int, 16> kMargin = {12, 13, 14, 15, 16, 17, 18, 132, 131, 130, 6, 2, 1, 7, 8, 0};
inline constexpr int kInnerCorner = 12;
inline constexpr int kOuterCorner = 131;
// The canthi, where the lids meet: what a face tracker marks as the eye's
// corners. dlib's inner corner falls on the caruncle, 40% of the way from its
// inner end (vertex 33) to the margin's corner (vertex 12): measured by fitting
// the model to the photos of ../shared/data with the pixels deciding.
inline constexpr int kInnerCanthusA = 33;
inline constexpr int kInnerCanthusB = 12;
inline constexpr double kInnerCanthusWeightB = 0.4;
inline constexpr int kOuterCanthus = 131;
inline constexpr std::array<int, 7> kUpperMargin = {13, 14, 15, 16, 17, 18, 132};
inline constexpr std::array<int, 7> kLowerMargin = {130, 6, 2, 1, 7, 8, 0};

// Six concentric edge loops around the eye, from the margin outward. Column
// 10 is the outer corner; columns 1-9 run along the upper lid and 11-19 along
// the lower lid; column 0 sits at the inner corner.
inline constexpr int kLoopColumns = 20;
inline constexpr int kOuterCornerColumn = 10;
inline constexpr std::array<std::array<int, kLoopColumns>, 6> kLoops = {{
    {33, 32, 25, 13, 14, 15, 16, 17, 18, 132, 131, 130, 6, 2, 1, 7, 8, 0, 28, 30},
    {35, 36, 26, 24, 23, 22, 21, 20, 19, 93, 112, 113, 5, 4, 3, 9, 10, 11, 29, 34},
    {83, 82, 77, 62, 61, 60, 37, 38, 39, 92, 139, 136, 40, 41, 42, 43, 44, 45, 46, 84},
    {86, 85, 78, 72, 71, 70, 47, 48, 49, 135, 141, 140, 53, 54, 55, 56, 57, 58, 59, 87},
    {80, 79, 76, 75, 74, 73, 50, 51, 52, 137, 138, 142, 63, 64, 65, 66, 67, 68, 69, 81},
    {101, 102, 103, 104, 105, 88, 89, 90, 91, 146, 145, 143, 94, 95, 96, 217, 97, 98, 99, 100},
}};
// The inner-corner vertex the lid rotation axes pass through.
inline constexpr int kRigInnerCorner = 34;

// Brow points k = lerp(A_k, B_k, w_k), from the inner to the outer end.
inline constexpr std::array<int, 6> kBrowA = {160, 161, 109, 166, 167, 168};
inline constexpr std::array<int, 6> kBrowB = {157, 156, 108, 144, 147, 153};
inline constexpr std::array<double, 6> kBrowWeight = {0.5, 0.5, 0.5, 0.5, 0.75, 1.0};

// The eyeball's limbus: a ring of 32 vertices at 10.75 mm forward, radius 5.87 mm.
inline constexpr std::array<int, 32> kLimbus = {3,  7,  11, 14, 18, 21, 25, 29, 33, 37,  41,  45,  49,  52,  56,  60,
                                                64, 68, 72, 76, 80, 84, 88, 92, 96, 100, 104, 108, 112, 116, 120, 124};
inline constexpr double kLimbusRadiusMm = 5.87;
inline constexpr double kLimbusDepthMm = 10.75;
inline constexpr double kLimbusUvRadius = 0.1385;  // measured: uv = 0.5 + 0.1385 (x, z) / 5.87 mm on the cornea
// The eyeball texture's pupil radius relative to the limbus's (measured on
// eyeball_grey.png: the black disc spans 443-581 of 1024 texels).
inline constexpr double kTexturePupilSize = 0.49;
inline constexpr double kScleraRadiusMm = 12.05;
// The corneal bulge's central part is a sphere of 6.84 mm centred 6.22 mm in
// front of the eyeball's centre (a sphere fitted to the mesh's cornea vertices
// beyond 12.5 mm: residual 0.016 mm).
inline constexpr double kCorneaCentreMm = 6.22;

}  // namespace gazedirector::topology
