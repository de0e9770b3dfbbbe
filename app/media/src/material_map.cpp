/// \file
/// \brief The material table and label mapping of `encode --material-map`: see material_map.h.

#include "depthtouch/media/material_map.h"

#include <cmath>
#include <cstdio>
#include <optional>

#include <toml++/toml.h>

#include "depthtouch/media/image_io.h"
#include "depthtouch/media/material_track.h"
#include "depthtouch/platform/file_access.h"
#include "depthtouch/platform/message_text.h"

namespace depthtouch::media {

namespace {

/// The presets (docs/materials.md "Presets"): stiffness as a scale of --stiffness, μs, μd.
/// Chosen to be told apart by touch, with friction of the order published for a fingertip on
/// such surfaces; not measured material constants.
constexpr MaterialPreset kPresets[] = {
    {"skin", {0.5, 0.6, 0.5}},  {"cloth", {0.25, 0.5, 0.4}},  {"wood", {1.5, 0.45, 0.35}},
    {"metal", {3.0, 0.3, 0.2}}, {"rubber", {0.75, 1.2, 1.0}},
};

/// Largest codable value of each key: 255 codes.
constexpr double kMaxStiffnessScale = 255.0 * scene::kStiffnessScalePerCode;
constexpr double kMaxFriction = 255.0 * scene::kFrictionPerCode;

std::string tableError(const std::string &path, const std::string &why)
{
    return "--materials " + platform::quotedText(path) + ": " + why;
}

/// \return the colour of "#rrggbb" \a text, nullopt when malformed.
std::optional<std::array<std::uint8_t, 3>> parseColor(const std::string &text)
{
    if (text.size() != 7 || text[0] != '#')
        return std::nullopt;
    std::array<std::uint8_t, 3> rgb{};
    for (std::size_t i = 0; i < 3; ++i) {
        unsigned v = 0;
        for (std::size_t k = 1 + 2 * i; k < 3 + 2 * i; ++k) {
            const char c = text[k];
            const int d = c >= '0' && c <= '9'   ? c - '0'
                          : c >= 'a' && c <= 'f' ? c - 'a' + 10
                          : c >= 'A' && c <= 'F' ? c - 'A' + 10
                                                 : -1;
            if (d < 0)
                return std::nullopt;
            v = v * 16 + static_cast<unsigned>(d);
        }
        rgb[i] = static_cast<std::uint8_t>(v);
    }
    return rgb;
}

std::string colorText(const std::uint8_t *rgb)
{
    char buf[8];
    std::snprintf(buf, sizeof buf, "#%02x%02x%02x", rgb[0], rgb[1], rgb[2]);
    return buf;
}

/// Stores number node \a n into \a field when it is within 0..\a max. \return false otherwise.
bool storeRanged(const toml::node &n, double max, double &field)
{
    const std::optional<double> v =
        n.is_integer() || n.is_floating_point() ? n.value<double>() : std::optional<double>{};
    if (!v || !std::isfinite(*v) || *v < 0.0 || *v > max)
        return false;
    field = *v;
    return true;
}

/// Parses material \a name from its table \a t. \return "" or the reason (without the path).
std::string parseMaterial(const std::string &name, const toml::table &t, NamedMaterial &m)
{
    m.name = name;
    const std::string what = "material " + platform::quotedText(name);
    if (const toml::node *p = t.get("preset")) {
        const std::optional<std::string> preset = p->value<std::string>();
        const MaterialPreset *found = nullptr;
        for (const MaterialPreset &row : kPresets)
            if (preset && *preset == row.name)
                found = &row;
        if (found == nullptr)
            return what + ": unknown preset (use skin, cloth, wood, metal or rubber)";
        m.material = found->material;
    }
    bool haveLabel = false;
    for (const auto &[k, node] : t) {
        const std::string key(k.str());
        bool ok = true;
        if (key == "label") {
            const std::optional<std::string> text = node.value<std::string>();
            const auto rgb = text ? parseColor(*text) : std::nullopt;
            if (!rgb)
                return what + ": label must be a colour \"#rrggbb\"";
            m.label = *rgb;
            haveLabel = true;
        } else if (key == "stiffness_scale") {
            ok = storeRanged(node, kMaxStiffnessScale, m.material.stiffnessScale);
        } else if (key == "static_friction") {
            ok = storeRanged(node, kMaxFriction, m.material.staticFriction);
        } else if (key == "dynamic_friction") {
            ok = storeRanged(node, kMaxFriction, m.material.dynamicFriction);
        } else if (key != "preset") {
            return what + ": unknown key " + platform::quotedText(key) +
                   " (use label, preset, stiffness_scale, static_friction, dynamic_friction)";
        }
        if (!ok)
            return what + ": " + key + " must be a number in 0.." +
                   (key == "stiffness_scale" ? "3.984375" : "2.55");
    }
    if (!haveLabel)
        return what + ": no label colour (label = \"#rrggbb\")";
    return {};
}

} // namespace

std::span<const MaterialPreset> materialPresets() noexcept
{
    return kPresets;
}

std::string parseMaterialTable(std::string_view text, const std::string &path,
                               std::vector<NamedMaterial> &out)
{
    toml::table table;
    try {
        table = toml::parse(text, path);
    } catch (const toml::parse_error &e) {
        return tableError(path, "line " + std::to_string(e.source().begin.line) + ": " +
                                    platform::printableText(e.description()));
    }
    out.clear();
    for (const auto &[k, node] : table) {
        const std::string name(k.str());
        const toml::table *t = node.as_table();
        if (t == nullptr)
            return tableError(path, "unknown key " + platform::quotedText(name) +
                                        " (each material is a table: [name])");
        NamedMaterial m;
        if (std::string why = parseMaterial(name, *t, m); !why.empty())
            return tableError(path, why);
        for (const NamedMaterial &other : out)
            if (other.label == m.label)
                return tableError(path, "materials " + platform::quotedText(other.name) + " and " +
                                            platform::quotedText(name) + " have the same label " +
                                            colorText(m.label.data()));
        out.push_back(std::move(m));
    }
    if (out.empty())
        return tableError(path, "no material");
    return {};
}

std::string mapLabels(const Image &labels, const std::string &labelsPath,
                      const std::vector<NamedMaterial> &table, Image &codes)
{
    if (labels.empty() || labels.format != PixelFormat::Rgb24)
        return "--material-map " + platform::quotedText(labelsPath) + ": not an RGB picture";
    codes = Image::make(labels.width, labels.height, PixelFormat::Rgb24);
    const NamedMaterial *last = nullptr;
    for (int y = 0; y < labels.height; ++y) {
        const std::uint8_t *in = labels.row(y);
        std::uint8_t *out = codes.row(y);
        for (int x = 0; x < labels.width; ++x, in += 3, out += 3) {
            // Label images are mostly runs of one colour: try the last material first.
            if (last == nullptr || last->label[0] != in[0] || last->label[1] != in[1] ||
                last->label[2] != in[2]) {
                last = nullptr;
                for (const NamedMaterial &m : table)
                    if (m.label[0] == in[0] && m.label[1] == in[1] && m.label[2] == in[2])
                        last = &m;
            }
            if (last == nullptr)
                return "--material-map " + platform::quotedText(labelsPath) + ": label colour " +
                       colorText(in) + " (pixel " + std::to_string(x) + ", " + std::to_string(y) +
                       ") has no material in --materials";
            scene::encodeMaterial(last->material, out);
        }
    }
    return {};
}

std::unique_ptr<FrameSource> openMaterialMap(const std::string &labelsPath,
                                             const std::string &tablePath, double fps,
                                             std::string &error)
{
    auto bytes = platform::readFileBounded(tablePath, kMaxMaterialTableBytes);
    if (!bytes) {
        char why[160];
        error = tableError(tablePath, bytes.error().format(why, sizeof why));
        return nullptr;
    }
    std::vector<NamedMaterial> table;
    const std::string text(bytes->begin(), bytes->end());
    if (error = parseMaterialTable(text, tablePath, table); !error.empty())
        return nullptr;
    auto labels = media::readImage(labelsPath, PixelFormat::Rgb24);
    if (!labels) {
        char why[160];
        error = "--material-map " + platform::quotedText(labelsPath) + ": " +
                labels.error().format(why, sizeof why);
        return nullptr;
    }
    Image codes;
    if (error = mapLabels(*labels, labelsPath, table, codes); !error.empty())
        return nullptr;
    return media::makeStillFrameSource(std::move(codes), fps, "material map " + labelsPath);
}

} // namespace depthtouch::media
