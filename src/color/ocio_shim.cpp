// The only code that sees OpenColorIO (2.1, C++ API): loads a config, builds
// the scene_linear -> display/view(+look) CPU processor and applies it. Every
// OCIO exception becomes a pb_result with a one-line message naming the
// config; nothing C++ crosses color.h.
#include <OpenColorIO/OpenColorIO.h>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <new>
#include <sstream>
#include <string>

extern "C" {
#include "color/color.h"
#include "core/result.h"
}

namespace OCIO = OCIO_NAMESPACE;

struct pb_color {
  std::string config_name; // "built-in" or a path (with "$OCIO=" when from the environment)
  std::string display, view, look;
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

pb_result load_config(const pb_color_desc *desc, pb_color *c) {
  const char *path = desc->config;
  const char *env = std::getenv("OCIO");
  if (empty(path) && !empty(env)) {
    path = env;
    c->config_name = std::string("$OCIO=") + env;
  } else if (!empty(path)) {
    c->config_name = path;
  } else {
    c->config_name = "built-in";
  }
  try {
    if (empty(path)) {
      std::istringstream in(pb_color_builtin_config_text);
      c->config = OCIO::Config::CreateFromStream(in);
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
  }
  return PB_OK;
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
  const char *cfg = c->config_name.c_str();
  try {
    const char *display = empty(desc->display) ? c->config->getDefaultDisplay() : desc->display;
    if (!has_display(c->config, display)) {
      r = pb_fail(PB_ERR_USAGE, "OCIO config %s: no display '%s' (displays: %s)", cfg, display,
                  join_displays(c->config).c_str());
      delete c;
      return r;
    }
    const char *view = empty(desc->view) ? c->config->getDefaultView(display) : desc->view;
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
    c->display = display;
    c->view = view;
    c->look = look;

    OCIO::DisplayViewTransformRcPtr dvt = OCIO::DisplayViewTransform::Create();
    dvt->setSrc(OCIO::ROLE_SCENE_LINEAR);
    dvt->setDisplay(display);
    dvt->setView(view);
    OCIO::ConstProcessorRcPtr proc;
    if (*look) {
      // The look replaces the view's own looks, as Blender's "Look" menu does.
      OCIO::LegacyViewingPipelineRcPtr vp = OCIO::LegacyViewingPipeline::Create();
      vp->setDisplayViewTransform(dvt);
      vp->setLooksOverrideEnabled(true);
      vp->setLooksOverride(look);
      proc = vp->getProcessor(c->config, c->config->getCurrentContext());
    } else {
      proc = c->config->getProcessor(dvt);
    }
    // Lossless: no fast pow/log approximations, so that the Standard view
    // matches the analytic sRGB encode to float precision.
    c->cpu = proc->getOptimizedCPUProcessor(OCIO::BIT_DEPTH_F32, OCIO::BIT_DEPTH_F32,
                                            OCIO::OPTIMIZATION_LOSSLESS);
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

extern "C" void pb_color_list(const pb_color *c, FILE *f) {
  std::fprintf(f, "config %s\n", c->config_name.c_str());
  for (int i = 0; i < c->config->getNumDisplays(); ++i) {
    const char *d = c->config->getDisplay(i);
    std::fprintf(f, "display %s: %s\n", d, join_views(c->config, d).c_str());
  }
  std::fprintf(f, "looks: %s\n", join_looks(c->config).c_str());
}
