#pragma once
/// \file
/// \brief `encode --material-map labels.png --materials materials.toml`: a label image (each
/// distinct colour one label) and a TOML table of named materials, turned into the material
/// track's codes (depthtouch/scene/material.h, docs/materials.md).
///
/// The table: one TOML table per material, keyed by its name:
/// ```toml
/// [skin]
/// label = "#ff0000"        # the label colour in the label image (required, "#rrggbb")
/// preset = "skin"          # optional: start from a built-in preset (materialPresets())
/// stiffness_scale = 0.6    # scale of --stiffness, 0..3.984375 (255/64)
/// static_friction = 0.5    # μs, 0..2.55
/// dynamic_friction = 0.4   # μd, 0..2.55
/// ```
/// Keys not given come from the preset, else stiffness scale 1 and no friction. Values are
/// rounded to the nearest code (1/64, 1/100). Errors are one line naming the file and the
/// material or pixel: a syntax error, an unknown key or preset, a value of the wrong type or out
/// of the codable range, a missing or malformed label, two materials with one label, a label
/// colour in the image that the table lacks (named with one pixel position), a missing file.
/// Thread-safety: reentrant (no shared state).

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "depthtouch/media/frame_source.h"
#include "depthtouch/media/image.h"
#include "depthtouch/scene/material.h"

namespace depthtouch::media {

/// Largest materials.toml read, bytes.
inline constexpr std::size_t kMaxMaterialTableBytes = std::size_t{1} << 20;

/// \brief A built-in material (docs/materials.md, "Presets").
struct MaterialPreset {
    const char *name;
    scene::Material material;
};

/// \return the built-in presets: skin, cloth, wood, metal, rubber.
std::span<const MaterialPreset> materialPresets() noexcept;

/// \brief One row of the table.
struct NamedMaterial {
    std::string name;                  ///< The TOML table's key.
    std::array<std::uint8_t, 3> label; ///< R, G, B of its label colour.
    scene::Material material;
};

/// \brief Parses the TOML \a text (from \a path, for messages) into \a out.
/// \return an empty string, or the one error line.
std::string parseMaterialTable(std::string_view text, const std::string &path,
                               std::vector<NamedMaterial> &out);

/// \brief The material codes of each pixel of \a labels (Rgb24, from \a labelsPath for
/// messages) through \a table, into \a codes (Rgb24, the same size).
/// \return an empty string, or the one error line naming the first colour the table lacks and
/// one pixel (column, row) that has it.
std::string mapLabels(const Image &labels, const std::string &labelsPath,
                      const std::vector<NamedMaterial> &table, Image &codes);

/// \brief Reads \a labelsPath (any picture FFmpeg reads, as RGB24) and \a tablePath, and maps
/// them (mapLabels()). \return the material codes as a still FrameSource at \a fps frames/s, or
/// nullptr with \a error set to the one error line.
std::unique_ptr<FrameSource> openMaterialMap(const std::string &labelsPath,
                                             const std::string &tablePath, double fps,
                                             std::string &error);

} // namespace depthtouch::media
