// The only code that sees OpenColorIO (2.1, C++ API): loads a config, builds
// the scene_linear -> display/view(+look) CPU processor and applies it. Every
// OCIO exception becomes a pb_result with a one-line message naming the
// config; nothing C++ crosses color.h.
#include <OpenColorIO/OpenColorIO.h>
#include <zlib.h>

#include <dirent.h>
#include <limits.h>
#include <stdlib.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <new>
#include <sstream>
#include <string>
#include <vector>

extern "C" {
#include "color/color.h"
#include "color/agx_builtin.h"
#include "color/filmic_builtin.h"
#include "core/result.h"
}

namespace OCIO = OCIO_NAMESPACE;

struct pb_color {
  std::string config_name; // "built-in" or a path ("$OCIO=" / "Blender's " before it when found so)
  std::string display, view, look;
  bool found_blender = false; // the config is an installed Blender's, found (not named)
  double exposure = 0.0, gamma = 1.0;
  OCIO::ConstConfigRcPtr config;
  OCIO::ConstCPUProcessorRcPtr cpu;
};

namespace {

bool empty(const char *s) { return !s || !*s; }

// One line: OCIO messages sometimes span several.
std::string one_line(const char *what) {
  std::string s = what ? what : "";
  for (char &ch : s)
    if (ch == '\n' || ch == '\r') ch = ' ';
  return s;
}

std::string join_displays(const OCIO::ConstConfigRcPtr &cfg) {
  std::string s;
  for (int i = 0; i < cfg->getNumDisplays(); ++i) {
    if (i) s += ", ";
    s += cfg->getDisplay(i);
  }
  return s.empty() ? "none" : s;
}

std::string join_views(const OCIO::ConstConfigRcPtr &cfg, const char *display) {
  std::string s;
  for (int i = 0; i < cfg->getNumViews(display); ++i) {
    if (i) s += ", ";
    s += cfg->getView(display, i);
  }
  return s.empty() ? "none" : s;
}

std::string join_looks(const OCIO::ConstConfigRcPtr &cfg) {
  std::string s = "None";
  for (int i = 0; i < cfg->getNumLooks(); ++i) {
    s += ", ";
    s += cfg->getLookNameByIndex(i);
  }
  return s;
}

bool has_display(const OCIO::ConstConfigRcPtr &cfg, const char *d) {
  for (int i = 0; i < cfg->getNumDisplays(); ++i)
    if (std::strcmp(cfg->getDisplay(i), d) == 0) return true;
  return false;
}

bool has_view(const OCIO::ConstConfigRcPtr &cfg, const char *d, const char *v) {
  for (int i = 0; i < cfg->getNumViews(d); ++i)
    if (std::strcmp(cfg->getView(d, i), v) == 0) return true;
  return false;
}

// The built-in config's reference is ACES2065-1: its scene-linear Rec.709
// back from it (the inverse of that colour space's to_scene_reference), the
// first steps of every view below that Blender's config builds from
// scene-linear Rec.709.
void append_to_rec709(const OCIO::GroupTransformRcPtr &g) {
  OCIO::BuiltinTransformRcPtr to_ap1 = OCIO::BuiltinTransform::Create();
  to_ap1->setStyle("ACEScg_to_ACES2065-1");
  to_ap1->setDirection(OCIO::TRANSFORM_DIR_INVERSE);
  OCIO::BuiltinTransformRcPtr to_rec709 = OCIO::BuiltinTransform::Create();
  to_rec709->setStyle("UTILITY - ACES-AP1_to_LINEAR-REC709_BFD");
  g->appendTransform(to_ap1);
  g->appendTransform(to_rec709);
}

OCIO::AllocationTransformRcPtr lg2_allocation(double lo, double hi) {
  OCIO::AllocationTransformRcPtr a = OCIO::AllocationTransform::Create();
  a->setAllocation(OCIO::ALLOCATION_LG2);
  const float vars[2] = {(float)lo, (float)hi};
  a->setVars(2, vars);
  return a;
}

// Blender's "Linear Rec.709 -> sRGB" (ExponentWithLinear 2.4 / 0.055, inverse).
OCIO::ExponentWithLinearTransformRcPtr srgb_encode() {
  OCIO::ExponentWithLinearTransformRcPtr e = OCIO::ExponentWithLinearTransform::Create();
  const double gamma[4] = {2.4, 2.4, 2.4, 1.0}, offset[4] = {0.055, 0.055, 0.055, 0.0};
  e->setGamma(gamma);
  e->setOffset(offset);
  e->setDirection(OCIO::TRANSFORM_DIR_INVERSE);
  return e;
}

// An n^3 cube from src/color/agx_builtin.c (base64, zlib, differences along
// red, 16 bits, entries x scale; see agx_builtin.h). Throws OCIO::Exception
// when the embedded data does not decode (a broken build).
OCIO::Lut3DTransformRcPtr embedded_cube(const char *base64, unsigned long deflated_size, int n,
                                        double scale) {
  static const signed char dec[256] = {
#define X64 -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1
      X64, X64, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, 62, -1, -1, -1, 63,
      52, 53, 54, 55, 56, 57, 58, 59, 60, 61, -1, -1, -1, -1, -1, -1,
      -1, 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14,
      15, 16, 17, 18, 19, 20, 21, 22, 23, 24, 25, -1, -1, -1, -1, -1,
      -1, 26, 27, 28, 29, 30, 31, 32, 33, 34, 35, 36, 37, 38, 39, 40,
      41, 42, 43, 44, 45, 46, 47, 48, 49, 50, 51, -1, -1, -1, -1, -1,
      X64, X64, X64, X64, X64, X64, X64, X64};
#undef X64
  std::vector<unsigned char> z;
  z.reserve(deflated_size + 4);
  unsigned acc = 0;
  int bits = 0;
  for (const char *p = base64; *p && *p != '='; ++p) {
    const int v = dec[(unsigned char)*p];
    if (v < 0) throw OCIO::Exception("built-in AgX: bad base64 in the embedded cube");
    acc = (acc << 6) | (unsigned)v;
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      z.push_back((unsigned char)(acc >> bits));
      acc &= (1u << bits) - 1u;
    }
  }
  const size_t count = (size_t)n * n * n * 3;
  std::vector<unsigned char> raw(count * 2);
  uLongf raw_size = (uLongf)raw.size();
  if (z.size() != deflated_size ||
      uncompress(raw.data(), &raw_size, z.data(), (uLong)z.size()) != Z_OK || raw_size != raw.size())
    throw OCIO::Exception("built-in AgX: the embedded cube does not inflate");
  OCIO::Lut3DTransformRcPtr cube = OCIO::Lut3DTransform::Create(n);
  cube->setInterpolation(OCIO::INTERP_TETRAHEDRAL);
  for (int b = 0; b < n; ++b)
    for (int g = 0; g < n; ++g) {
      unsigned prev[3] = {0, 0, 0};
      for (int r = 0; r < n; ++r) {
        float v[3];
        for (int k = 0; k < 3; ++k) {
          const size_t i = ((((size_t)b * n + g) * n + r) * 3 + k) * 2;
          prev[k] = (prev[k] + (unsigned)(raw[i] | raw[i + 1] << 8)) & 0xffffu;
          v[k] = (float)(prev[k] / scale);
        }
        cube->setValue(r, g, b, v[0], v[1], v[2]);
      }
    }
  return cube;
}

OCIO::Lut3DTransformRcPtr agx_cube() {
  return embedded_cube(pb_agx_cube_base64, pb_agx_cube_deflated_size, PB_AGX_CUBE_SIZE, 65535.0);
}

OCIO::MatrixTransformRcPtr matrix3(const double m3[9], bool inverse = false) {
  double m[16] = {0};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) m[4 * i + j] = m3[3 * i + j];
  m[15] = 1.0;
  OCIO::MatrixTransformRcPtr t = OCIO::MatrixTransform::Create();
  t->setMatrix(m);
  if (inverse) t->setDirection(OCIO::TRANSFORM_DIR_INVERSE);
  return t;
}

// Blender 4.x's AgX view on an sRGB display ("AgX Base sRGB"), from the data
// and steps of src/color/agx_builtin.h.
OCIO::ConstTransformRcPtr agx_transform() {
  OCIO::GroupTransformRcPtr g = OCIO::GroupTransform::Create();
  append_to_rec709(g);
  g->appendTransform(matrix3(pb_agx_rec709_to_egamut));
  g->appendTransform(lg2_allocation(PB_AGX_LOG_MIN, PB_AGX_LOG_MAX));
  g->appendTransform(agx_cube());
  OCIO::ExponentTransformRcPtr power = OCIO::ExponentTransform::Create();
  const double e[4] = {PB_AGX_EXPONENT, PB_AGX_EXPONENT, PB_AGX_EXPONENT, 1.0};
  power->setValue(e);
  g->appendTransform(power);
  g->appendTransform(srgb_encode());
  return g;
}

// Blender 4.x's "AgX Log" (the process space of its AgX looks), from the
// data and steps of src/color/agx_builtin.h: from the scene reference,
// through Blender's "Luminance Compensation Rec.2020" (a 37^3 cube on the
// lg2-encoded E-Gamut values), to Rec.2020, the inset / rotation, lg2; back,
// lg2 inverse, the inset inverted, Rec.2020 to Rec.709, as Blender's.
OCIO::ColorSpaceRcPtr agx_log_colorspace() {
  OCIO::GroupTransformRcPtr from = OCIO::GroupTransform::Create();
  append_to_rec709(from);
  from->appendTransform(matrix3(pb_agx_rec709_to_egamut));
  from->appendTransform(lg2_allocation(PB_AGX_LOG_MIN, PB_AGX_LOG_MAX));
  OCIO::Lut3DTransformRcPtr lumcomp = embedded_cube(pb_agx_lumcomp_cube_base64, pb_agx_lumcomp_cube_deflated_size,
                                                    PB_AGX_LUMCOMP_CUBE_SIZE, PB_AGX_LUMCOMP_SCALE);
  from->appendTransform(lumcomp);
  OCIO::AllocationTransformRcPtr unlog = lg2_allocation(PB_AGX_LOG_MIN, PB_AGX_LOG_MAX);
  unlog->setDirection(OCIO::TRANSFORM_DIR_INVERSE);
  from->appendTransform(unlog);
  from->appendTransform(matrix3(pb_agx_egamut_to_rec2020));
  from->appendTransform(matrix3(pb_agx_log_inset));
  from->appendTransform(lg2_allocation(PB_AGX_LOG_MIN, PB_AGX_LOG_MAX));

  OCIO::GroupTransformRcPtr to = OCIO::GroupTransform::Create();
  to->appendTransform(unlog->createEditableCopy());
  to->appendTransform(matrix3(pb_agx_log_inset, true));
  to->appendTransform(matrix3(pb_agx_rec2020_to_rec709));
  OCIO::GroupTransformRcPtr back = OCIO::GroupTransform::Create();
  append_to_rec709(back);
  back->setDirection(OCIO::TRANSFORM_DIR_INVERSE);
  to->appendTransform(back);

  OCIO::ColorSpaceRcPtr cs = OCIO::ColorSpace::Create();
  cs->setName("AgX Log");
  cs->setFamily("Log Encodings");
  cs->setDescription("Blender 4.x's AgX Log: luminance compensation, inset and rotation of primaries, "
                     "25 stops of log (the process space of the AgX looks)");
  cs->setTransform(from, OCIO::COLORSPACE_DIR_FROM_REFERENCE);
  cs->setTransform(to, OCIO::COLORSPACE_DIR_TO_REFERENCE);
  return cs;
}

// Adds the looks of a `looks:` YAML section (Blender's own text, from
// src/color/agx_builtin.c) to cfg: OpenColorIO parses them, in a config of
// their process spaces' names only, so that they are Blender's to the letter.
void add_yaml_looks(const OCIO::ConfigRcPtr &cfg, const char *looks_yaml) {
  std::string text = "ocio_profile_version: 2.1\nroles: {default: Raw}\ncolorspaces:\n"
                     "  - !<ColorSpace> {name: Raw, isdata: true}\n";
  for (int i = 0; i < cfg->getNumColorSpaces(); ++i)
    if (std::strcmp(cfg->getColorSpaceNameByIndex(i), "Raw") != 0)
      text += std::string("  - !<ColorSpace> {name: \"") + cfg->getColorSpaceNameByIndex(i) + "\"}\n";
  text += looks_yaml;
  std::istringstream in(text);
  OCIO::ConstConfigRcPtr parsed = OCIO::Config::CreateFromStream(in);
  for (int i = 0; i < parsed->getNumLooks(); ++i) cfg->addLook(parsed->getLook(parsed->getLookNameByIndex(i)));
}

// The Khronos PBR Neutral tone mapper (Khronos PBR Neutral specification,
// start 0.8 - 0.04, desaturation 0.15) on linear Rec.709, in place.
void pbr_neutral(double c[3]) {
  const double start = 0.8 - 0.04, desat = 0.15;
  const double x = std::min(c[0], std::min(c[1], c[2]));
  const double offset = x < 0.08 ? x - 6.25 * x * x : 0.04;
  for (int k = 0; k < 3; ++k) c[k] -= offset;
  const double peak = std::max(c[0], std::max(c[1], c[2]));
  if (peak < start) return;
  const double d = 1.0 - start;
  const double new_peak = 1.0 - d * d / (peak + d - start);
  const double g = 1.0 - 1.0 / (desat * (peak - new_peak) + 1.0);
  for (int k = 0; k < 3; ++k) c[k] = c[k] * new_peak / peak * (1.0 - g) + new_peak * g;
}

// Blender 4.2+'s "Khronos PBR Neutral sRGB": the formula sampled on the grid
// of Blender's pbrNeutral.cube (57^3 on lg2 [-9, 10], which that file is, to
// its 7 decimals: config/ocio/bake_agx.py checks it), tetrahedral, then the
// sRGB encode.
OCIO::ConstTransformRcPtr pbr_neutral_transform() {
  const int n = PB_PBR_NEUTRAL_CUBE_SIZE;
  const double lo = PB_PBR_NEUTRAL_LOG_MIN, span = PB_PBR_NEUTRAL_LOG_MAX - PB_PBR_NEUTRAL_LOG_MIN;
  OCIO::Lut3DTransformRcPtr cube = OCIO::Lut3DTransform::Create(n);
  cube->setInterpolation(OCIO::INTERP_TETRAHEDRAL);
  std::vector<double> lin(n);
  for (int i = 0; i < n; ++i) lin[i] = std::exp2(lo + span * i / (n - 1));
  for (int r = 0; r < n; ++r)
    for (int g = 0; g < n; ++g)
      for (int b = 0; b < n; ++b) {
        double c[3] = {lin[r], lin[g], lin[b]};
        pbr_neutral(c);
        cube->setValue(r, g, b, (float)c[0], (float)c[1], (float)c[2]);
      }
  OCIO::GroupTransformRcPtr g = OCIO::GroupTransform::Create();
  append_to_rec709(g);
  g->appendTransform(lg2_allocation(PB_PBR_NEUTRAL_LOG_MIN, PB_PBR_NEUTRAL_LOG_MAX));
  g->appendTransform(cube);
  g->appendTransform(srgb_encode());
  return g;
}

// Blender 3.4's Filmic curve (pb_filmic_curve, or one of a look's) as a 1D
// LUT, interpolated linearly as Blender's config does with the file.
OCIO::Lut1DTransformRcPtr filmic_curve(const float *curve, bool inverse = false) {
  OCIO::Lut1DTransformRcPtr lut = OCIO::Lut1DTransform::Create(PB_FILMIC_CURVE_SIZE, false);
  lut->setInterpolation(OCIO::INTERP_LINEAR);
  for (int i = 0; i < PB_FILMIC_CURVE_SIZE; ++i) lut->setValue(i, curve[i], curve[i], curve[i]);
  if (inverse) lut->setDirection(OCIO::TRANSFORM_DIR_INVERSE);
  return lut;
}

// Blender 3.4's "Filmic Log" from the built-in config's reference, from the
// closed form in src/color/filmic_builtin.h (config/ocio/bake_filmic.py
// derives it from Blender's files): scene-linear Rec.709, the lg2 shaper,
// the 65^3 desaturation cube evaluated on its grid here and interpolated
// tetrahedrally, as Blender's config does with the file, then x / 0.66.
OCIO::GroupTransformRcPtr filmic_log_transform() {
  const int n = PB_FILMIC_CUBE_SIZE;
  const double lo = PB_FILMIC_LOG_MIN, span = PB_FILMIC_LOG_MAX - PB_FILMIC_LOG_MIN;
  OCIO::Lut3DTransformRcPtr cube = OCIO::Lut3DTransform::Create(n);
  cube->setInterpolation(OCIO::INTERP_TETRAHEDRAL);
  double lin[PB_FILMIC_CUBE_SIZE];
  for (int i = 0; i < n; ++i) lin[i] = std::exp2(lo + span * i / (n - 1));
  auto encode = [&](double v) {
    double x = (std::log2(v) - lo) / span;
    return (float)(x > PB_FILMIC_CUBE_FLOOR ? x : PB_FILMIC_CUBE_FLOOR);
  };
  for (int r = 0; r < n; ++r)
    for (int g = 0; g < n; ++g)
      for (int b = 0; b < n; ++b) {
        const int m = std::max(r, std::max(g, b));
        const double t = pb_filmic_desat_t[m], top = lin[m];
        cube->setValue(r, g, b, encode(lin[r] + t * (top - lin[r])),
                       encode(lin[g] + t * (top - lin[g])), encode(lin[b] + t * (top - lin[b])));
      }
  OCIO::AllocationTransformRcPtr rescale = OCIO::AllocationTransform::Create();
  rescale->setAllocation(OCIO::ALLOCATION_UNIFORM);
  const float rescale_vars[2] = {0.0f, (float)PB_FILMIC_CURVE_MAX};
  rescale->setVars(2, rescale_vars);

  OCIO::GroupTransformRcPtr g = OCIO::GroupTransform::Create();
  append_to_rec709(g);
  g->appendTransform(lg2_allocation(PB_FILMIC_LOG_MIN, PB_FILMIC_LOG_MAX));
  g->appendTransform(cube);
  g->appendTransform(rescale);
  return g;
}

// Blender 3.4's Filmic view for the built-in config: Filmic Log, then the
// base contrast curve (Blender's "Filmic sRGB").
OCIO::ConstTransformRcPtr filmic_transform() {
  OCIO::GroupTransformRcPtr g = filmic_log_transform();
  g->appendTransform(filmic_curve(pb_filmic_curve));
  return g;
}

// "Filmic Log" as a colour space (the process space of the Filmic looks):
// back to the reference as Blender's, an lg2 allocation over 16.5 stops,
// inverse (not the desaturation undone).
OCIO::ColorSpaceRcPtr filmic_log_colorspace() {
  OCIO::GroupTransformRcPtr to = OCIO::GroupTransform::Create();
  OCIO::AllocationTransformRcPtr unlog = lg2_allocation(PB_FILMIC_LOG_MIN, PB_FILMIC_LOG_LOOK_MAX);
  unlog->setDirection(OCIO::TRANSFORM_DIR_INVERSE);
  to->appendTransform(unlog);
  OCIO::GroupTransformRcPtr back = OCIO::GroupTransform::Create();
  append_to_rec709(back);
  back->setDirection(OCIO::TRANSFORM_DIR_INVERSE);
  to->appendTransform(back);
  OCIO::ColorSpaceRcPtr cs = OCIO::ColorSpace::Create();
  cs->setName("Filmic Log");
  cs->setFamily("Log Encodings");
  cs->setDescription("Blender 3.4's Filmic Log: the process space of the Filmic looks");
  cs->setTransform(filmic_log_transform(), OCIO::COLORSPACE_DIR_FROM_REFERENCE);
  cs->setTransform(to, OCIO::COLORSPACE_DIR_TO_REFERENCE);
  return cs;
}

// Blender's Filmic looks: in Filmic Log, the look's curve then the base
// curve inverted (nothing for "Medium Contrast").
void add_filmic_looks(const OCIO::ConfigRcPtr &cfg) {
  for (const pb_filmic_look &fl : pb_filmic_looks) {
    OCIO::GroupTransformRcPtr g = OCIO::GroupTransform::Create();
    if (fl.curve >= 0) {
      g->appendTransform(filmic_curve(pb_filmic_look_curves[fl.curve]));
      g->appendTransform(filmic_curve(pb_filmic_curve, true));
    }
    OCIO::LookRcPtr look = OCIO::Look::Create();
    look->setName(fl.name);
    look->setProcessSpace("Filmic Log");
    look->setTransform(g);
    cfg->addLook(look);
  }
}

// The built-in config with its Filmic, AgX and Khronos PBR Neutral views,
// their process spaces "Filmic Log" and "AgX Log" and Blender's Filmic and
// AgX looks added (OCIO's YAML cannot hold an in-memory LUT, so they are
// added here); Filmic is the default, as in Blender 3.4.
OCIO::ConstConfigRcPtr builtin_config() {
  std::istringstream in(pb_color_builtin_config_text);
  OCIO::ConfigRcPtr cfg = OCIO::Config::CreateFromStream(in)->createEditableCopy();
  OCIO::ColorSpaceRcPtr cs = OCIO::ColorSpace::Create();
  cs->setName("Filmic sRGB");
  cs->setFamily("Display");
  cs->setDescription("Blender 3.4's Filmic view on an sRGB display (base contrast, no look)");
  cs->setTransform(filmic_transform(), OCIO::COLORSPACE_DIR_FROM_REFERENCE);
  cfg->addColorSpace(cs);
  cfg->addDisplayView("sRGB", "Filmic", "Filmic sRGB", "");
  cfg->addColorSpace(filmic_log_colorspace());
  cs = OCIO::ColorSpace::Create();
  cs->setName("AgX Base sRGB");
  cs->setFamily("Display");
  cs->setDescription("Blender 4.x's AgX view on an sRGB display (AgX Base, no look)");
  cs->setTransform(agx_transform(), OCIO::COLORSPACE_DIR_FROM_REFERENCE);
  cfg->addColorSpace(cs);
  cfg->addDisplayView("sRGB", "AgX", "AgX Base sRGB", "");
  cfg->addColorSpace(agx_log_colorspace());
  add_filmic_looks(cfg);
  add_yaml_looks(cfg, pb_agx_looks_yaml);
  cs = OCIO::ColorSpace::Create();
  cs->setName("Khronos PBR Neutral sRGB");
  cs->setFamily("Display");
  cs->setDescription("Blender 4.2+'s Khronos PBR Neutral view on an sRGB display");
  cs->setTransform(pbr_neutral_transform(), OCIO::COLORSPACE_DIR_FROM_REFERENCE);
  cfg->addColorSpace(cs);
  cfg->addDisplayView("sRGB", "Khronos PBR Neutral", "Khronos PBR Neutral sRGB", "");
  cfg->setActiveViews("Filmic, AgX, Khronos PBR Neutral, Standard, ACES 1.0 - SDR Video, Raw");
  return cfg;
}

bool readable(const std::string &path) {
  FILE *f = std::fopen(path.c_str(), "rb");
  if (!f) return false;
  std::fclose(f);
  return true;
}

pb_result load_config(const pb_color_desc *desc, pb_color *c) {
  const char *path = desc->config;
  const char *env = std::getenv("OCIO");
  if (!empty(path) && std::strcmp(path, "built-in") == 0) {
    path = nullptr; // asked for by name
    c->config_name = "built-in";
  } else if (empty(path) && !empty(env)) {
    path = env;
    c->config_name = std::string("$OCIO=") + env;
  } else if (!empty(path)) {
    c->config_name = path;
  } else if (desc->purpose == PB_COLOR_PICTURE && (path = pb_color_blender_config())) {
    c->config_name = std::string("Blender's ") + path;
    c->found_blender = true;
  } else {
    c->config_name = "built-in";
  }
  try {
    if (empty(path)) {
      c->config = builtin_config();
    } else {
      FILE *f = std::fopen(path, "rb");
      if (!f)
        return pb_fail(PB_ERR_IO, "OCIO config %s: cannot open: %s", c->config_name.c_str(),
                       std::strerror(errno));
      std::fclose(f);
      c->config = OCIO::Config::CreateFromFile(path);
    }
    c->config->validate();
  } catch (const OCIO::Exception &e) {
    return pb_fail(PB_ERR_NOT_AVAILABLE, "OCIO config %s: %s", c->config_name.c_str(),
                   one_line(e.what()).c_str());
  } catch (const std::bad_alloc &) {
    return pb_fail(PB_ERR_NOMEM, "OCIO config %s: out of memory", c->config_name.c_str());
  }
  return PB_OK;
}

// The display processor of c's display / view / look and gamma with the
// given exposure (throws OCIO::Exception).
OCIO::ConstCPUProcessorRcPtr make_cpu(const pb_color *c, double exposure) {
  OCIO::DisplayViewTransformRcPtr dvt = OCIO::DisplayViewTransform::Create();
  dvt->setSrc(OCIO::ROLE_SCENE_LINEAR);
  dvt->setDisplay(c->display.c_str());
  dvt->setView(c->view.c_str());
  // Blender's display processor (OCIOImpl::createDisplayProcessor):
  // exposure as a scale in scene-linear, the look (replacing the view's own
  // looks, as Blender's "Look" menu does), the view, then gamma as an
  // exponent 1/gamma on the display values.
  OCIO::LegacyViewingPipelineRcPtr vp = OCIO::LegacyViewingPipeline::Create();
  vp->setDisplayViewTransform(dvt);
  if (!c->look.empty()) {
    vp->setLooksOverrideEnabled(true);
    vp->setLooksOverride(c->look.c_str());
  }
  if (exposure != 0.0) {
    const double k = std::exp2(exposure);
    const double m[16] = {k, 0, 0, 0, 0, k, 0, 0, 0, 0, k, 0, 0, 0, 0, 1};
    OCIO::MatrixTransformRcPtr scale = OCIO::MatrixTransform::Create();
    scale->setMatrix(m);
    vp->setLinearCC(scale);
  }
  if (c->gamma != 1.0) {
    const double e = 1.0 / c->gamma;
    const double v[4] = {e, e, e, 1.0};
    OCIO::ExponentTransformRcPtr ex = OCIO::ExponentTransform::Create();
    ex->setValue(v);
    vp->setDisplayCC(ex);
  }
  OCIO::ConstProcessorRcPtr proc = vp->getProcessor(c->config, c->config->getCurrentContext());
  // Lossless: no fast pow/log approximations, so that the Standard view
  // matches the analytic sRGB encode to float precision.
  return proc->getOptimizedCPUProcessor(OCIO::BIT_DEPTH_F32, OCIO::BIT_DEPTH_F32,
                                          OCIO::OPTIMIZATION_LOSSLESS);
}

} // namespace

extern "C" pb_result pb_color_open(const pb_color_desc *desc, pb_color **out) {
  static const pb_color_desc zero = {};
  if (!desc) desc = &zero;
  *out = nullptr;
  pb_color *c = new (std::nothrow) pb_color();
  if (!c) return pb_fail(PB_ERR_NOMEM, "OCIO: out of memory");
  pb_result r = load_config(desc, c);
  if (r != PB_OK) {
    delete c;
    return r;
  }
  // A Blender config found on this machine (not named by the user) that
  // lacks the display, view or look asked for -- an older Blender's, e.g.
  // 3.4's without AgX, asked for a 4.x scene's view -- gives way to the
  // built-in one when that has them.
  if (c->found_blender) {
    try {
      auto holds = [&](const OCIO::ConstConfigRcPtr &cf) {
        const char *d = empty(desc->display) ? cf->getDefaultDisplay() : desc->display;
        if (!has_display(cf, d)) return false;
        if (!empty(desc->view) && !has_view(cf, d, desc->view)) return false;
        return empty(desc->look) || std::strcmp(desc->look, "None") == 0 || cf->getLook(desc->look) != nullptr;
      };
      OCIO::ConstConfigRcPtr b;
      if (!holds(c->config) && holds(b = builtin_config())) {
        c->config = b;
        c->config_name = "built-in (" + c->config_name.substr(std::strlen("Blender's ")) +
                         " lacks the display, view or look asked for)";
        c->found_blender = false;
      }
    } catch (const OCIO::Exception &) {
      // keep the found config; the checks below name what it lacks
    }
  }
  const char *cfg = c->config_name.c_str();
  try {
    const char *display = empty(desc->display) ? c->config->getDefaultDisplay() : desc->display;
    if (!has_display(c->config, display)) {
      r = pb_fail(PB_ERR_USAGE, "OCIO config %s: no display '%s' (displays: %s)", cfg, display,
                  join_displays(c->config).c_str());
      delete c;
      return r;
    }
    // Without --view: pictures get Blender's default view transform (Filmic
    // for every new Blender 3.4 scene; Blender's config lists Standard first,
    // so OCIO's own default would be Standard), metrics get Standard.
    const char *view = desc->view;
    const char *want = desc->purpose == PB_COLOR_METRICS ? "Standard" : "Filmic";
    if (empty(view))
      view = has_view(c->config, display, want) ? want : c->config->getDefaultView(display);
    if (!has_view(c->config, display, view)) {
      r = pb_fail(PB_ERR_USAGE, "OCIO config %s: display '%s' has no view '%s' (views: %s)", cfg,
                  display, view, join_views(c->config, display).c_str());
      delete c;
      return r;
    }
    const char *look = (empty(desc->look) || std::strcmp(desc->look, "None") == 0) ? "" : desc->look;
    if (*look && !c->config->getLook(look)) {
      r = pb_fail(PB_ERR_USAGE, "OCIO config %s: no look '%s' (looks: %s)", cfg, look,
                  join_looks(c->config).c_str());
      delete c;
      return r;
    }
    if (!std::isfinite(desc->exposure) || std::fabs(desc->exposure) > 64.0 ||
        !std::isfinite(desc->gamma) || desc->gamma < 0.0 || (desc->gamma > 0.0 && desc->gamma < 1e-3)) {
      r = pb_fail(PB_ERR_USAGE, "OCIO config %s: exposure %g / gamma %g out of range "
                  "(exposure within +-64 stops, gamma > 0.001)", cfg, desc->exposure, desc->gamma);
      delete c;
      return r;
    }
    c->display = display;
    c->view = view;
    c->look = look;
    c->exposure = desc->exposure;
    c->gamma = desc->gamma > 0.0 ? desc->gamma : 1.0;

    c->cpu = make_cpu(c, c->exposure);
  } catch (const OCIO::Exception &e) {
    r = pb_fail(PB_ERR_NOT_AVAILABLE, "OCIO config %s: display '%s', view '%s': %s", cfg,
                c->display.c_str(), c->view.c_str(), one_line(e.what()).c_str());
    delete c;
    return r;
  } catch (const std::bad_alloc &) {
    delete c;
    return pb_fail(PB_ERR_NOMEM, "OCIO config %s: out of memory", cfg);
  }
  *out = c;
  return PB_OK;
}

extern "C" void pb_color_destroy(pb_color *c) { delete c; }

static pb_result apply(const OCIO::ConstCPUProcessorRcPtr &cpu, const std::string &cfg,
                       float *pixels, uint32_t width, uint32_t height, uint32_t channels) {
  if (channels != 3 && channels != 4)
    return pb_fail(PB_ERR_IMAGE, "OCIO config %s: %u channels (3 or 4 expected)", cfg.c_str(),
                   channels);
  if (width == 0 || height == 0) return PB_OK;
  try {
    OCIO::PackedImageDesc img(pixels, (long)width, (long)height, (long)channels);
    cpu->apply(img);
  } catch (const OCIO::Exception &e) {
    return pb_fail(PB_ERR_NOT_AVAILABLE, "OCIO config %s: %s", cfg.c_str(),
                   one_line(e.what()).c_str());
  }
  return PB_OK;
}

extern "C" pb_result pb_color_apply_display(const pb_color *c, float *pixels, uint32_t width,
                                            uint32_t height, uint32_t channels) {
  pb_result r = apply(c->cpu, c->config_name, pixels, width, height, channels);
  if (r != PB_OK) return r;
  const size_t n = (size_t)width * height;
  for (size_t i = 0; i < n; ++i)
    for (uint32_t k = 0; k < 3; ++k) {
      float &v = pixels[i * channels + k];
      v = v > 0.0f ? (v < 1.0f ? v : 1.0f) : 0.0f; // NaN -> 0
    }
  return PB_OK;
}

extern "C" pb_result pb_color_convert(const pb_color *c, const char *src, const char *dst,
                                      float *pixels, uint32_t width, uint32_t height,
                                      uint32_t channels) {
  OCIO::ConstCPUProcessorRcPtr cpu;
  try {
    for (const char *name : {src, dst})
      if (!c->config->getColorSpace(name))
        return pb_fail(PB_ERR_USAGE, "OCIO config %s: no colour space '%s'",
                       c->config_name.c_str(), name);
    cpu = c->config->getProcessor(src, dst)->getOptimizedCPUProcessor(
        OCIO::BIT_DEPTH_F32, OCIO::BIT_DEPTH_F32, OCIO::OPTIMIZATION_LOSSLESS);
  } catch (const OCIO::Exception &e) {
    return pb_fail(PB_ERR_NOT_AVAILABLE, "OCIO config %s: %s -> %s: %s", c->config_name.c_str(),
                   src, dst, one_line(e.what()).c_str());
  }
  return apply(cpu, c->config_name, pixels, width, height, channels);
}

extern "C" const char *pb_color_config_name(const pb_color *c) { return c->config_name.c_str(); }
extern "C" const char *pb_color_display(const pb_color *c) { return c->display.c_str(); }
extern "C" const char *pb_color_view(const pb_color *c) { return c->view.c_str(); }
extern "C" const char *pb_color_look(const pb_color *c) { return c->look.c_str(); }
extern "C" double pb_color_exposure(const pb_color *c) { return c->exposure; }
extern "C" double pb_color_gamma(const pb_color *c) { return c->gamma; }

extern "C" void pb_color_describe(const pb_color *c, char *buf, size_t size) {
  std::snprintf(buf, size, "%s / %s, look %s, exposure %g, gamma %g (OCIO config %s)",
                c->display.c_str(), c->view.c_str(), c->look.empty() ? "None" : c->look.c_str(),
                c->exposure, c->gamma, c->config_name.c_str());
}

extern "C" const char *pb_color_blender_config(void) {
  // Searched on every call (a few stat calls) so that tests can change
  // $PB_BLENDER_OCIO; not thread-safe, like the rest of colour set-up.
  static std::string found;
  found.clear();
  const char *env = std::getenv("PB_BLENDER_OCIO");
  if (env) {
    if (*env && readable(env)) found = env;
    return found.empty() ? nullptr : found.c_str();
  }
  const std::string tail = "/datafiles/colormanagement/config.ocio";
  std::vector<std::string> dirs = {"/usr/share/blender"};
  // Blender's own tarballs keep X.Y/datafiles beside the executable.
  if (const char *path = std::getenv("PATH")) {
    std::string p = path;
    for (size_t a = 0; a <= p.size();) {
      size_t b = p.find(':', a);
      if (b == std::string::npos) b = p.size();
      std::string d = p.substr(a, b - a);
      if (!d.empty() && readable(d + "/blender")) {
        char real[PATH_MAX];
        if (realpath((d + "/blender").c_str(), real)) {
          std::string r = real;
          dirs.push_back(r.substr(0, r.rfind('/')));
        }
      }
      a = b + 1;
    }
  }
  for (const std::string &d : dirs) {
    if (readable(d + tail)) {
      found = d + tail;
      break;
    }
    // Versioned folders (X.Y/datafiles), newest first.
    std::vector<std::string> versions;
    if (DIR *dir = opendir(d.c_str())) {
      while (struct dirent *e = readdir(dir))
        if (e->d_name[0] >= '0' && e->d_name[0] <= '9') versions.push_back(e->d_name);
      closedir(dir);
    }
    std::sort(versions.begin(), versions.end(), [](const std::string &x, const std::string &y) {
      return std::strtod(x.c_str(), nullptr) > std::strtod(y.c_str(), nullptr);
    });
    for (const std::string &v : versions)
      if (readable(d + "/" + v + tail)) {
        found = d + "/" + v + tail;
        break;
      }
    if (!found.empty()) break;
  }
  return found.empty() ? nullptr : found.c_str();
}

extern "C" void pb_color_list(const pb_color *c, FILE *f) {
  std::fprintf(f, "config %s\n", c->config_name.c_str());
  for (int i = 0; i < c->config->getNumDisplays(); ++i) {
    const char *d = c->config->getDisplay(i);
    std::fprintf(f, "display %s: %s\n", d, join_views(c->config, d).c_str());
  }
  std::fprintf(f, "looks: %s\n", join_looks(c->config).c_str());
}

namespace {

// The view on n RGB triples, clamped to [0, 1] as pb_color_apply_display.
void eval_rgb(const OCIO::ConstCPUProcessorRcPtr &cpu, std::vector<float> &rgb) {
  const long n = (long)(rgb.size() / 3);
  OCIO::PackedImageDesc img(rgb.data(), n, 1, 3);
  cpu->apply(img);
  for (float &v : rgb) v = v > 0.0f ? (v < 1.0f ? v : 1.0f) : 0.0f;
}

} // namespace

static pb_result bake_lut(const pb_color *c, uint32_t size, pb_color_lut *out);

extern "C" pb_result pb_color_bake_lut(const pb_color *c, uint32_t size, pb_color_lut *out) {
  if (size) return bake_lut(c, size, out);
  // Default: 66 nodes; a view whose bake misses by more than half an 8-bit
  // step there (Filmic's saturated colours: its desaturation curves between
  // the nodes) gets 129 (34 MB, bakes in about a second).
  pb_result r = bake_lut(c, 66, out);
  if (r != PB_OK || out->max_error * 255.0 <= 0.5) return r;
  pb_color_lut fine;
  if (bake_lut(c, 129, &fine) != PB_OK) {
    pb_error_clear();
    return PB_OK; /* the coarser one stays */
  }
  if (fine.max_error < out->max_error) {
    pb_color_lut_destroy(out);
    *out = fine;
  } else {
    pb_color_lut_destroy(&fine);
  }
  return PB_OK;
}

static pb_result bake_lut(const pb_color *c, uint32_t size, pb_color_lut *out) {
  std::memset(out, 0, sizeof *out);
  if (size < 3 || size > 129)
    return pb_fail(PB_ERR_USAGE, "OCIO config %s: a %u^3 LUT (3 .. 129 nodes per axis)",
                   c->config_name.c_str(), size);
  try {
    OCIO::ConstCPUProcessorRcPtr cpu = make_cpu(c, 0.0);
    // The shaper's range from probes (color.h): grey and the three
    // primaries at 2^t, t = -24 .. 20 in 1/16 stops, and at 0.
    const int steps = 44 * 16 + 1, hues = 4;
    auto tof = [](int i) { return -24.0 + i / 16.0; };
    std::vector<float> p((size_t)hues * (steps + 1) * 3, 0.0f);
    for (int h = 0; h < hues; ++h)
      for (int i = 0; i < steps; ++i)
        for (int k = 0; k < 3; ++k)
          p[((size_t)h * (steps + 1) + i) * 3 + k] = (h == 0 || h == k + 1) ? (float)std::exp2(tof(i)) : 0.0f;
    eval_rgb(cpu, p); // entry `steps` of each hue: x = 0
    auto at = [&](int h, int i, int k) { return p[((size_t)h * (steps + 1) + i) * 3 + k]; };
    // hi: from here up, every probe is what the top probe is (1e-6).
    int hi = steps - 1;
    while (hi > 0) {
      bool same = true;
      for (int h = 0; h < hues && same; ++h)
        for (int k = 0; k < 3; ++k) same = same && std::fabs(at(h, hi - 1, k) - at(h, steps - 1, k)) <= 1e-6f;
      if (!same) break;
      --hi;
    }
    // lo: the largest t below hi under which the view is linear in x
    // (f(x) = f(0) + (f(2^lo) - f(0)) x / 2^lo within 2e-5).
    int lo = hi - 16 > 0 ? hi - 16 : 0;
    for (; lo > 0; --lo) {
      bool linear = true;
      for (int h = 0; h < hues && linear; ++h)
        for (int k = 0; k < 3 && linear; ++k) {
          const float f0 = at(h, steps, k), fl = at(h, lo, k);
          for (int j = 0; j < lo && linear; ++j)
            linear = std::fabs(at(h, j, k) - (f0 + (fl - f0) * (float)std::exp2(tof(j) - tof(lo)))) <= 2e-5f;
        }
      if (linear) break;
    }
    // A flat bottom (Filmic's allocation floor: the view constant below
    // it) found to float precision by bisection, so that a log allocation's
    // own grid can start there.
    double lo_t = tof(lo);
    {
      bool flat = true;
      for (int h = 0; h < hues && flat; ++h)
        for (int k = 0; k < 3 && flat; ++k) flat = std::fabs(at(h, lo, k) - at(h, steps, k)) <= 1e-6f;
      if (flat && lo + 1 < hi) {
        double a = tof(lo), b = tof(lo + 1);
        for (int it = 0; it < 40; ++it) {
          const double m = 0.5 * (a + b);
          std::vector<float> t((size_t)hues * 3, 0.0f);
          for (int h = 0; h < hues; ++h)
            for (int k = 0; k < 3; ++k) t[(size_t)h * 3 + k] = (h == 0 || h == k + 1) ? (float)std::exp2(m) : 0.0f;
          eval_rgb(cpu, t);
          bool same = true;
          for (int h = 0; h < hues && same; ++h)
            for (int k = 0; k < 3; ++k) same = same && std::fabs(t[(size_t)h * 3 + k] - at(h, steps, k)) <= 1e-6f;
          (same ? a : b) = m;
        }
        lo_t = a;
      }
    }
    out->size = size;
    const size_t n = (size_t)size * size * size;
    out->rgba = (float *)std::malloc(n * 4 * sizeof(float));
    float *best = (float *)std::malloc(n * 4 * sizeof(float));
    if (!out->rgba || !best) {
      std::free(best);
      throw std::bad_alloc();
    }
    // The bake's error: a grey ramp 2^-24 .. 2^16 (1/8 stops) and 4096
    // colours with channels 0 or 2^U(-14, 8) (a fixed LCG).
    std::vector<float> q;
    for (int i = 0; i <= 40 * 8; ++i)
      for (int k = 0; k < 3; ++k) q.push_back((float)std::exp2(-24.0 + i / 8.0));
    uint64_t s = 0x9e3779b97f4a7c15ull;
    for (int i = 0; i < 3 * 4096; ++i) {
      s = s * 6364136223846793005ull + 1442695040888963407ull;
      const double u = (double)(s >> 11) / 9007199254740992.0;
      q.push_back(u < 0.1 ? 0.0f : (float)std::exp2(-14.0 + 22.0 * (u - 0.1) / 0.9));
    }
    std::vector<float> ref = q;
    eval_rgb(cpu, ref);
    // Candidate ranges: the probed one, and (a flat bottom) 25 stops from
    // it, the span of Blender's Filmic log allocation (-12.47 .. 12.53),
    // whose own 65^3 cube then lies node on node with 66 nodes (64 log
    // cells). The one with the smaller error over the probes is kept.
    double cand[2][2] = {{lo_t, tof(hi)}, {lo_t, lo_t + 25.0}};
    double best_err = 1e30;
    float best_lo = 0, best_hi = 0;
    for (int ci = 0; ci < 2; ++ci) {
      if (ci == 1 && cand[1][1] < cand[0][1]) continue; /* would clip what the view still changes */
      out->lo = (float)cand[ci][0];
      out->hi = (float)cand[ci][1];
      std::vector<float> xs(size);
      xs[0] = 0.0f;
      for (uint32_t i = 1; i < size; ++i)
        xs[i] = std::exp2f(out->lo + (float)(i - 1) * ((out->hi - out->lo) / (float)(size - 2)));
      std::vector<float> grid(n * 3);
      for (uint32_t b = 0; b < size; ++b)
        for (uint32_t g = 0; g < size; ++g)
          for (uint32_t r = 0; r < size; ++r) {
            float *o = &grid[(((size_t)b * size + g) * size + r) * 3];
            o[0] = xs[r], o[1] = xs[g], o[2] = xs[b];
          }
      eval_rgb(cpu, grid);
      for (size_t i = 0; i < n; ++i) {
        for (int k = 0; k < 3; ++k) out->rgba[4 * i + k] = grid[3 * i + k];
        out->rgba[4 * i + 3] = 1.0f;
      }
      double err = 0.0;
      for (size_t i = 0; i < q.size(); i += 3) {
        float v[3];
        pb_color_lut_eval(out, 1.0f, &q[i], v);
        for (int k = 0; k < 3; ++k) err = std::max(err, (double)std::fabs(v[k] - ref[i + k]));
      }
      if (err < best_err) {
        best_err = err, best_lo = out->lo, best_hi = out->hi;
        std::memcpy(best, out->rgba, n * 4 * sizeof(float));
      }
    }
    std::free(out->rgba);
    out->rgba = best;
    out->lo = best_lo, out->hi = best_hi;
    out->max_error = best_err;
  } catch (const OCIO::Exception &e) {
    pb_color_lut_destroy(out);
    return pb_fail(PB_ERR_NOT_AVAILABLE, "OCIO config %s: baking %s / %s: %s", c->config_name.c_str(),
                   c->display.c_str(), c->view.c_str(), one_line(e.what()).c_str());
  } catch (const std::bad_alloc &) {
    pb_color_lut_destroy(out);
    return pb_fail(PB_ERR_NOMEM, "OCIO config %s: out of memory baking a %u^3 LUT", c->config_name.c_str(), size);
  }
  return PB_OK;
}
