/* serve's JSON-lines protocol (protocol.h): a small JSON reader (RFC 8259:
 * objects, arrays, strings with escapes, numbers, true/false/null; nesting
 * at most 16 deep, at most 512 values a line), the requests decoded from
 * it, and the reply lines. */
#include "serve/protocol.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "render/photon/tracer.h"

/* ---- the JSON reader ------------------------------------------------------ */

enum { JV_NULL, JV_BOOL, JV_NUMBER, JV_STRING, JV_ARRAY, JV_OBJECT };
enum { MAX_VALUES = 512, MAX_DEPTH = 16 };

typedef struct jv {
  int type;
  double num;
  int b;
  const char *str; /* decoded, NUL-terminated (strings; keys of members) */
  const char *key; /* the member's key inside an object, else NULL */
  int first, next; /* children (arrays, objects) and siblings, -1: none */
  int count;
  const char *text; /* where the value starts in the line, and its length */
  size_t text_len;
} jv;

typedef struct reader {
  const char *p, *end;
  jv v[MAX_VALUES];
  int n;
  char *strbuf; /* decoded strings: at most the line's length */
  size_t strpos, strcap;
  char *err;
  size_t err_cap;
} reader;

static int rfail(reader *r, const char *fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  if (r->err && r->err[0] == 0) vsnprintf(r->err, r->err_cap, fmt, ap);
  va_end(ap);
  return -1;
}

static void skip_ws(reader *r) {
  while (r->p < r->end && (*r->p == ' ' || *r->p == '\t' || *r->p == '\r' || *r->p == '\n')) r->p++;
}

static int hex4(const char *p, unsigned *out) {
  unsigned x = 0;
  for (int i = 0; i < 4; ++i) {
    char c = p[i];
    x <<= 4;
    if (c >= '0' && c <= '9') x |= (unsigned)(c - '0');
    else if (c >= 'a' && c <= 'f') x |= (unsigned)(c - 'a' + 10);
    else if (c >= 'A' && c <= 'F') x |= (unsigned)(c - 'A' + 10);
    else return -1;
  }
  *out = x;
  return 0;
}

static void put_utf8(reader *r, unsigned cp) {
  char *o = r->strbuf + r->strpos;
  if (cp < 0x80) o[0] = (char)cp, r->strpos += 1;
  else if (cp < 0x800) o[0] = (char)(0xC0 | cp >> 6), o[1] = (char)(0x80 | (cp & 63)), r->strpos += 2;
  else if (cp < 0x10000)
    o[0] = (char)(0xE0 | cp >> 12), o[1] = (char)(0x80 | ((cp >> 6) & 63)), o[2] = (char)(0x80 | (cp & 63)),
    r->strpos += 3;
  else
    o[0] = (char)(0xF0 | cp >> 18), o[1] = (char)(0x80 | ((cp >> 12) & 63)), o[2] = (char)(0x80 | ((cp >> 6) & 63)),
    o[3] = (char)(0x80 | (cp & 63)), r->strpos += 4;
}

/* The length of the well-formed UTF-8 sequence at p (at most n bytes
 * there), 0 when it is not one (RFC 3629: no overlongs, no surrogates,
 * nothing above U+10FFFF). */
static size_t utf8_len(const unsigned char *p, size_t n) {
  if (p[0] < 0x80) return 1;
  size_t len = p[0] >= 0xF0 ? 4 : p[0] >= 0xE0 ? 3 : p[0] >= 0xC2 ? 2 : 0;
  if (!len || len > n || p[0] > 0xF4) return 0;
  for (size_t i = 1; i < len; ++i)
    if ((p[i] & 0xC0) != 0x80) return 0;
  if (len == 3 && ((p[0] == 0xE0 && p[1] < 0xA0) || (p[0] == 0xED && p[1] >= 0xA0))) return 0;
  if (len == 4 && ((p[0] == 0xF0 && p[1] < 0x90) || (p[0] == 0xF4 && p[1] >= 0x90))) return 0;
  return len;
}

/* A string at r->p (the opening quote); decoded into strbuf. An escape
 * never decodes to more bytes than it takes in the line (\uXXXX: 6 in, at
 * most 3 out; a surrogate pair: 12 in, 4 out), so strbuf of the line's
 * length plus one NUL per string is enough. */
static int parse_string(reader *r, const char **out) {
  r->p++;
  char *start = r->strbuf + r->strpos;
  for (;;) {
    if (r->p >= r->end) return rfail(r, "unterminated string");
    unsigned char c = (unsigned char)*r->p;
    if (c == '"') {
      r->p++;
      break;
    }
    if (c < 0x20) return rfail(r, "control character in a string");
    if (c >= 0x80) {
      size_t n = utf8_len((const unsigned char *)r->p, (size_t)(r->end - r->p));
      if (!n) return rfail(r, "a string is not UTF-8");
      memcpy(r->strbuf + r->strpos, r->p, n);
      r->strpos += n, r->p += n;
      continue;
    }
    if (c != '\\') {
      r->strbuf[r->strpos++] = (char)c;
      r->p++;
      continue;
    }
    if (r->p + 1 >= r->end) return rfail(r, "unterminated string");
    char e = r->p[1];
    r->p += 2;
    switch (e) {
      case '"': r->strbuf[r->strpos++] = '"'; break;
      case '\\': r->strbuf[r->strpos++] = '\\'; break;
      case '/': r->strbuf[r->strpos++] = '/'; break;
      case 'b': r->strbuf[r->strpos++] = '\b'; break;
      case 'f': r->strbuf[r->strpos++] = '\f'; break;
      case 'n': r->strbuf[r->strpos++] = '\n'; break;
      case 'r': r->strbuf[r->strpos++] = '\r'; break;
      case 't': r->strbuf[r->strpos++] = '\t'; break;
      case 'u': {
        unsigned cp, lo;
        if (r->end - r->p < 4 || hex4(r->p, &cp)) return rfail(r, "bad \\u escape in a string");
        r->p += 4;
        if (cp >= 0xD800 && cp < 0xDC00) {
          if (r->end - r->p < 6 || r->p[0] != '\\' || r->p[1] != 'u' || hex4(r->p + 2, &lo) || lo < 0xDC00 ||
              lo >= 0xE000)
            return rfail(r, "unpaired surrogate in a string");
          r->p += 6;
          cp = 0x10000 + ((cp - 0xD800) << 10) + (lo - 0xDC00);
        } else if (cp >= 0xDC00 && cp < 0xE000) {
          return rfail(r, "unpaired surrogate in a string");
        }
        if (cp == 0) return rfail(r, "\\u0000 in a string");
        put_utf8(r, cp);
        break;
      }
      default: return rfail(r, "bad escape '\\%c' in a string", e);
    }
  }
  r->strbuf[r->strpos++] = 0;
  *out = start;
  return 0;
}

static int parse_value(reader *r, int depth);

static int new_value(reader *r, int type) {
  if (r->n >= MAX_VALUES) return rfail(r, "more than %d values in one line", MAX_VALUES);
  jv *v = &r->v[r->n];
  memset(v, 0, sizeof *v);
  v->type = type, v->first = v->next = -1, v->text = r->p;
  return r->n++;
}

static int parse_container(reader *r, int depth, int object) {
  if (depth >= MAX_DEPTH) return rfail(r, "nested more than %d deep", MAX_DEPTH);
  int self = new_value(r, object ? JV_OBJECT : JV_ARRAY);
  if (self < 0) return -1;
  r->p++;
  skip_ws(r);
  int last = -1;
  if (r->p < r->end && *r->p == (object ? '}' : ']')) {
    r->p++;
    return self;
  }
  for (;;) {
    const char *key = NULL;
    skip_ws(r);
    if (object) {
      if (r->p >= r->end || *r->p != '"') return rfail(r, "expected a key string in an object");
      if (parse_string(r, &key)) return -1;
      skip_ws(r);
      if (r->p >= r->end || *r->p != ':') return rfail(r, "expected ':' after the key \"%s\"", key);
      r->p++;
    }
    int child = parse_value(r, depth + 1);
    if (child < 0) return -1;
    r->v[child].key = key;
    if (last < 0) r->v[self].first = child;
    else r->v[last].next = child;
    last = child;
    r->v[self].count++;
    skip_ws(r);
    if (r->p < r->end && *r->p == ',') {
      r->p++;
      continue;
    }
    if (r->p < r->end && *r->p == (object ? '}' : ']')) {
      r->p++;
      return self;
    }
    return rfail(r, object ? "expected ',' or '}' in an object" : "expected ',' or ']' in an array");
  }
}

static int parse_value(reader *r, int depth) {
  skip_ws(r);
  if (r->p >= r->end) return rfail(r, "unexpected end of the line");
  const char *start = r->p;
  int i;
  char c = *r->p;
  if (c == '{' || c == '[') {
    i = parse_container(r, depth, c == '{');
  } else if (c == '"') {
    if ((i = new_value(r, JV_STRING)) < 0) return -1;
    const char *s;
    if (parse_string(r, &s)) return -1;
    r->v[i].str = s;
  } else if (c == '-' || (c >= '0' && c <= '9')) {
    /* The JSON number grammar, then strtod on a copy. */
    const char *p = r->p;
    if (*p == '-') p++;
    if (p >= r->end || !(*p >= '0' && *p <= '9')) return rfail(r, "bad number");
    if (*p == '0') p++;
    else
      while (p < r->end && *p >= '0' && *p <= '9') p++;
    if (p < r->end && *p == '.') {
      p++;
      if (p >= r->end || !(*p >= '0' && *p <= '9')) return rfail(r, "bad number");
      while (p < r->end && *p >= '0' && *p <= '9') p++;
    }
    if (p < r->end && (*p == 'e' || *p == 'E')) {
      p++;
      if (p < r->end && (*p == '+' || *p == '-')) p++;
      if (p >= r->end || !(*p >= '0' && *p <= '9')) return rfail(r, "bad number");
      while (p < r->end && *p >= '0' && *p <= '9') p++;
    }
    char tmp[64];
    size_t len = (size_t)(p - r->p);
    if (len >= sizeof tmp) return rfail(r, "number too long");
    memcpy(tmp, r->p, len);
    tmp[len] = 0;
    if ((i = new_value(r, JV_NUMBER)) < 0) return -1;
    r->v[i].num = strtod(tmp, NULL);
    r->p = p;
  } else if (r->end - r->p >= 4 && memcmp(r->p, "true", 4) == 0) {
    if ((i = new_value(r, JV_BOOL)) < 0) return -1;
    r->v[i].b = 1, r->p += 4;
  } else if (r->end - r->p >= 5 && memcmp(r->p, "false", 5) == 0) {
    if ((i = new_value(r, JV_BOOL)) < 0) return -1;
    r->p += 5;
  } else if (r->end - r->p >= 4 && memcmp(r->p, "null", 4) == 0) {
    if ((i = new_value(r, JV_NULL)) < 0) return -1;
    r->p += 4;
  } else {
    if (c > 0x20 && c < 0x7f) return rfail(r, "unexpected character '%c'", c);
    return rfail(r, "unexpected byte 0x%02x", (unsigned)(unsigned char)c);
  }
  if (i >= 0) r->v[i].text = start, r->v[i].text_len = (size_t)(r->p - start);
  return i;
}

static const jv *member(const reader *r, const jv *obj, const char *key) {
  for (int i = obj->first; i >= 0; i = r->v[i].next)
    if (strcmp(r->v[i].key, key) == 0) return &r->v[i];
  return NULL;
}

/* ---- requests ----------------------------------------------------------- */

static const char *const cmd_names[PB_SERVE_CMD_COUNT] = {"camera", "resolution", "time",   "settings",
                                                          "frame",  "stream",     "reload", "quit"};

const char *pb_serve_cmd_name(pb_serve_cmd c) { return c < PB_SERVE_CMD_COUNT ? cmd_names[c] : "?"; }

/* The fields each request may carry (besides "cmd" and "id"). */
enum { MAX_FIELDS = 16 };
static const char *const fields[PB_SERVE_CMD_COUNT][MAX_FIELDS] = {
    {"view", "projection", "axes", "index"},
    {"width", "height"},
    {"t"},
    {"seed"}, /* and every setting of the table offered to requests (setting_row) */
    {""},
    {"on", "max_passes", "noise_threshold"},
    {"scene"},
    {""},
};

typedef struct req_ctx {
  reader *r;
  const jv *obj;
  const char *cmd;
} req_ctx;

static int bad(req_ctx *c, const char *fmt, ...) {
  char m[400];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(m, sizeof m, fmt, ap);
  va_end(ap);
  return rfail(c->r, "\"%s\": %s", c->cmd, m);
}

/* An integer field in [lo, hi]; 1 when present, 0 when absent, -1 bad. */
static int get_uint(req_ctx *c, const char *key, double lo, double hi, uint64_t *out) {
  const jv *v = member(c->r, c->obj, key);
  if (!v) return 0;
  if (v->type != JV_NUMBER || v->num != floor(v->num) || v->num < lo || v->num > hi)
    return bad(c, "\"%s\" must be an integer in [%.0f, %.0f]", key, lo, hi);
  *out = (uint64_t)v->num;
  return 1;
}

static int get_bool(req_ctx *c, const char *key, int *out) {
  const jv *v = member(c->r, c->obj, key);
  if (!v) return 0;
  if (v->type != JV_BOOL) return bad(c, "\"%s\" must be true or false", key);
  *out = v->b;
  return 1;
}

/* The row of the settings table (render/settings.h) a request may set
 * under `key`, or -1. */
static int setting_row(const char *key) {
  for (int i = 0; i < PB_SETTING_COUNT; ++i)
    if ((pb_setting_table[i].surfaces & PB_SURFACE_REQUEST) && strcmp(key, pb_setting_table[i].id) == 0) return i;
  return -1;
}

/* Setting i from the request, as its row says: an integer or a number in
 * its range, true or false, or one of its names. 0: not given, 1: set, -1:
 * bad (the message in c). */
static int get_setting(req_ctx *c, int i, pb_settings *s) {
  const pb_setting_info *t = &pb_setting_table[i];
  const jv *v = member(c->r, c->obj, t->id);
  if (!v) return 0;
  int ranged = t->lo != 0 || t->hi != 0;
  switch (t->kind) {
  case PB_SETTING_U32: {
    uint64_t u = 0;
    int g = get_uint(c, t->id, ranged ? t->lo : 0, ranged ? t->hi : 4294967295.0, &u);
    if (g <= 0) return g;
    pb_settings_set(s, i, (double)u);
    return 1;
  }
  case PB_SETTING_F64:
    if (v->type != JV_NUMBER || !isfinite(v->num) || (ranged && (v->num < t->lo || v->num > t->hi))) {
      if (ranged) return bad(c, "\"%s\" must be a number in [%g, %g]", t->id, t->lo, t->hi);
      return bad(c, "\"%s\" must be a finite number", t->id);
    }
    pb_settings_set(s, i, v->num);
    return 1;
  case PB_SETTING_BOOL: {
    int b = 0;
    int g = get_bool(c, t->id, &b);
    if (g <= 0) return g;
    pb_settings_set(s, i, b);
    return 1;
  }
  case PB_SETTING_CHOICE: {
    int k = 0;
    while (t->choices[k] && (v->type != JV_STRING || strcmp(v->str, t->choices[k]))) ++k;
    if (!t->choices[k]) {
      char list[256];
      size_t n = 0;
      list[0] = 0;
      for (int j = 0; t->choices[j] && n < sizeof list; ++j)
        n += (size_t)snprintf(list + n, sizeof list - n, "%s\"%s\"", j ? ", " : "", t->choices[j]);
      return bad(c, "\"%s\" must be one of %s", t->id, list);
    }
    pb_settings_set(s, i, k);
    return 1;
  }
  }
  return bad(c, "\"%s\": bad setting kind", t->id);
}

static int get_matrix(req_ctx *c, const char *key, double m[16]) {
  const jv *v = member(c->r, c->obj, key);
  if (!v) return bad(c, "needs \"%s\" (16 numbers, row-major)", key);
  int k = 0;
  if (v->type == JV_ARRAY && v->count == 16) {
    for (int i = v->first; i >= 0; i = c->r->v[i].next, ++k) {
      const jv *e = &c->r->v[i];
      if (e->type != JV_NUMBER || !isfinite(e->num)) break;
      m[k] = e->num;
    }
  }
  if (k != 16) return bad(c, "\"%s\" must be an array of 16 finite numbers (row-major)", key);
  return 1;
}

int pb_serve_parse(const char *line, size_t len, pb_serve_request *req, char *cmd_name, size_t cmd_cap, char *err,
                   size_t err_cap) {
  memset(req, 0, sizeof *req);
  req->camera_index = -1;
  if (cmd_cap) cmd_name[0] = 0;
  if (err_cap) err[0] = 0;
  reader *r = calloc(1, sizeof *r);
  char *strbuf = malloc(len + MAX_VALUES + 1);
  if (!r || !strbuf) {
    free(r);
    free(strbuf);
    snprintf(err, err_cap, "out of memory");
    return -1;
  }
  r->p = line, r->end = line + len, r->strbuf = strbuf, r->strcap = len + MAX_VALUES + 1;
  r->err = err, r->err_cap = err_cap;
  int rc = -1;
  if (len > PB_SERVE_MAX_LINE) {
    rfail(r, "the line is longer than %d bytes", PB_SERVE_MAX_LINE);
    goto done;
  }
  int root = parse_value(r, 0);
  if (root >= 0) skip_ws(r);
  if (root >= 0 && r->p != r->end) rfail(r, "text after the JSON value"), root = -1;
  if (root < 0) {
    char m[600];
    snprintf(m, sizeof m, "malformed JSON at byte %zu: %s", (size_t)(r->p - line) + 1, err);
    snprintf(err, err_cap, "%s", m);
    goto done;
  }
  const jv *obj = &r->v[root];
  if (obj->type != JV_OBJECT) {
    rfail(r, "a request is a JSON object ({\"cmd\": ...})");
    goto done;
  }
  const jv *id = member(r, obj, "id");
  if (id) {
    if ((id->type != JV_NUMBER && id->type != JV_STRING) || id->text_len >= sizeof req->id) {
      rfail(r, "\"id\" must be a number or a string of at most %zu characters", sizeof req->id - 3);
      goto done;
    }
    memcpy(req->id, id->text, id->text_len);
    req->id[id->text_len] = 0;
  }
  const jv *cmd = member(r, obj, "cmd");
  if (!cmd || cmd->type != JV_STRING) {
    rfail(r, "no \"cmd\" string (camera, resolution, time, settings, frame, stream, reload, quit)");
    goto done;
  }
  if (cmd_cap) snprintf(cmd_name, cmd_cap, "%s", cmd->str);
  int k = 0;
  while (k < PB_SERVE_CMD_COUNT && strcmp(cmd_names[k], cmd->str) != 0) ++k;
  if (k == PB_SERVE_CMD_COUNT) {
    rfail(r, "unknown command \"%.64s\" (camera, resolution, time, settings, frame, stream, reload, quit)",
          cmd->str);
    goto done;
  }
  req->cmd = (pb_serve_cmd)k;
  req_ctx c = {r, obj, cmd_names[k]};
  /* Every member must be one this request knows: a typo is an error, not
   * a silently ignored setting. */
  for (int i = obj->first; i >= 0; i = r->v[i].next) {
    const char *key = r->v[i].key;
    int known = strcmp(key, "cmd") == 0 || strcmp(key, "id") == 0;
    for (int f = 0; !known && f < MAX_FIELDS && fields[k][f] && fields[k][f][0]; ++f) known = strcmp(key, fields[k][f]) == 0;
    if (!known && k == PB_SERVE_SETTINGS) known = setting_row(key) >= 0;
    if (!known) {
      bad(&c, "unknown field \"%.64s\"", key);
      goto done;
    }
  }
  uint64_t u = 0;
  int g;
  switch (req->cmd) {
    case PB_SERVE_CAMERA: {
      if ((g = get_uint(&c, "index", 0, 1 << 20, &u)) < 0) goto done;
      if (g) {
        if (member(r, obj, "view") || member(r, obj, "projection")) {
          bad(&c, "either \"index\" or \"view\" and \"projection\"");
          goto done;
        }
        req->camera_index = (int)u;
        break;
      }
      if (get_matrix(&c, "view", req->view) < 0 || get_matrix(&c, "projection", req->projection) < 0) goto done;
      const jv *axes = member(r, obj, "axes");
      if (axes) {
        if (axes->type != JV_STRING || (strcmp(axes->str, "scene") && strcmp(axes->str, "blender"))) {
          bad(&c, "\"axes\" must be \"scene\" (glTF, Y up) or \"blender\" (Z up)");
          goto done;
        }
        req->blender_axes = strcmp(axes->str, "blender") == 0;
      }
      break;
    }
    case PB_SERVE_RESOLUTION: {
      uint64_t w = 0, h = 0;
      if ((g = get_uint(&c, "width", 1, 16384, &w)) <= 0 || get_uint(&c, "height", 1, 16384, &h) <= 0) {
        if (!err[0]) bad(&c, "needs \"width\" and \"height\" (integers in [1, 16384])");
        goto done;
      }
      req->width = (uint32_t)w, req->height = (uint32_t)h;
      break;
    }
    case PB_SERVE_TIME: {
      const jv *t = member(r, obj, "t");
      if (!t || t->type != JV_NUMBER || !isfinite(t->num)) {
        bad(&c, "needs \"t\" (seconds, a finite number)");
        goto done;
      }
      req->t = t->num;
      break;
    }
    case PB_SERVE_SETTINGS: {
      pb_serve_settings *s = &req->settings;
      pb_settings_init(&s->set);
      /* 2^53: the integers a double holds exactly. */
      if ((g = get_uint(&c, "seed", 0, 9007199254740992.0, &u)) < 0) goto done;
      if (g) s->seed_given = 1, s->seed = u;
      for (int i = 0; i < PB_SETTING_COUNT; ++i)
        if ((pb_setting_table[i].surfaces & PB_SURFACE_REQUEST) && get_setting(&c, i, &s->set) < 0) goto done;
      break;
    }
    case PB_SERVE_STREAM:
      if ((g = get_bool(&c, "on", &req->stream_on)) <= 0) {
        if (!err[0]) bad(&c, "needs \"on\" (true or false)");
        goto done;
      }
      if (get_uint(&c, "max_passes", 0, 1e9, &u) < 0) goto done;
      req->max_passes = (uint32_t)u;
      {
        const jv *nt = member(r, obj, "noise_threshold");
        if (nt && (nt->type != JV_NUMBER || !(nt->num >= 0 && nt->num <= 0.5))) {
          bad(&c, "\"noise_threshold\" must be a number in [0, 0.5] (RMS noise of the displayed image; 0: none)");
          goto done;
        }
        req->noise_threshold = nt ? nt->num : -1.0; /* -1: the session's --noise-threshold */
      }
      break;
    case PB_SERVE_RELOAD: {
      const jv *sc = member(r, obj, "scene");
      if (sc) {
        if (sc->type != JV_STRING || !sc->str[0] || strlen(sc->str) >= sizeof req->scene) {
          bad(&c, "\"scene\" must be a non-empty path shorter than %d bytes", PB_SERVE_MAX_PATH);
          goto done;
        }
        snprintf(req->scene, sizeof req->scene, "%s", sc->str);
      }
      break;
    }
    case PB_SERVE_FRAME:
    case PB_SERVE_QUIT:
    case PB_SERVE_CMD_COUNT: break;
  }
  rc = 0;
done:
  free(strbuf);
  free(r);
  return rc;
}

/* ---- the camera ------------------------------------------------------------ */

static double dot3(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

static int normalize3(double v[3]) {
  double l = sqrt(dot3(v, v));
  if (!(l > 1e-12) || !isfinite(l)) return -1;
  for (int k = 0; k < 3; ++k) v[k] /= l;
  return 0;
}

/* Blender's Z-up world to glTF's Y-up (the add-on's writer: x, z, -y). */
static void blender_to_gltf(double v[3]) {
  double y = v[1];
  v[1] = v[2];
  v[2] = -y;
}

int pb_serve_camera_from_matrices(const double V[16], const double P[16], int blender_axes, pb_camera *out,
                                  char *err, size_t err_cap) {
  for (int i = 0; i < 16; ++i)
    if (!isfinite(V[i]) || !isfinite(P[i])) {
      snprintf(err, err_cap, "camera: a matrix has a non-finite entry");
      return -1;
    }
  /* V = [R t; 0 1] with R's rows the camera's right, up and back (-forward)
   * in world coordinates; the position is -R^T t. */
  double right[3] = {V[0], V[1], V[2]}, up[3] = {V[4], V[5], V[6]}, back[3] = {V[8], V[9], V[10]};
  double t[3] = {V[3], V[7], V[11]};
  double pos[3];
  for (int k = 0; k < 3; ++k) pos[k] = -(right[k] * t[0] + up[k] * t[1] + back[k] * t[2]);
  /* The rows' lengths (a view matrix with scale): the position needs
   * R^-1 = R^T / s^2 for a uniform scale s. */
  double s2 = dot3(right, right);
  if (!(s2 > 1e-24) || fabs(V[12]) + fabs(V[13]) + fabs(V[14]) > 1e-9 || fabs(V[15] - 1.0) > 1e-9) {
    snprintf(err, err_cap, "camera: \"view\" is not a rigid world-to-camera matrix (last row 0 0 0 1)");
    return -1;
  }
  for (int k = 0; k < 3; ++k) pos[k] /= s2;
  /* Gram-Schmidt: forward first (the view axis), then up, right = forward x up. */
  double fwd[3] = {-back[0], -back[1], -back[2]};
  if (normalize3(fwd)) goto singular;
  double d = dot3(up, fwd);
  for (int k = 0; k < 3; ++k) up[k] -= d * fwd[k];
  if (normalize3(up)) goto singular;
  double rt[3] = {fwd[1] * up[2] - fwd[2] * up[1], fwd[2] * up[0] - fwd[0] * up[2], fwd[0] * up[1] - fwd[1] * up[0]};
  if (dot3(rt, right) < 0) goto singular; /* a mirrored frame */
  if (blender_axes) {
    blender_to_gltf(pos), blender_to_gltf(fwd), blender_to_gltf(up), blender_to_gltf(rt);
  }
  pb_camera c;
  memset(&c, 0, sizeof c);
  snprintf(c.name, sizeof c.name, "serve");
  for (int k = 0; k < 3; ++k)
    c.position[k] = (float)pos[k], c.forward[k] = (float)fwd[k], c.up[k] = (float)up[k], c.right[k] = (float)rt[k];
  c.fit = PB_CAMERA_FIT_VERTICAL;
  if (P[14] == 0.0 && fabs(P[15] - 1.0) < 1e-9) {
    /* Orthographic: x_ndc = P00 x + P03, y_ndc = P11 y + P13, z_ndc = P22 z + P23. */
    if (!(P[0] > 0) || !(P[5] > 0) || P[10] == 0) goto bad_proj;
    c.orthographic = 1;
    c.ortho_size = (float)(2.0 / P[5]);
    c.aspect = (float)(P[5] / P[0]);
    /* The window's centre (-P03 / P00, -P13 / P11) in units of the fitted
     * (vertical) side, 2 / P11 (camera.c: shift x extent). */
    c.shift[0] = (float)((-P[3] / P[0]) * P[5] / 2.0);
    c.shift[1] = (float)(-P[7] / 2.0);
    double n = (P[11] + 1.0) / P[10], f = (P[11] - 1.0) / P[10];
    if (n < 0 && f > n) {
      /* A clip range reaching behind the view's position (Blender's
       * orthographic views clip at -clip_end / 2): the same rays start on
       * a plane moved back by -n. */
      for (int k = 0; k < 3; ++k) c.position[k] -= (float)(-n) * c.forward[k];
      f -= n, n = 0;
    }
    c.znear = n > 0 ? (float)n : 0.0f;
    c.zfar = f > n && f > 0 ? (float)f : 0.0f;
  } else if (P[14] == -1.0 && P[15] == 0.0) {
    /* Perspective (glFrustum): x_ndc = P00 x/-z - P02, so the window at
     * distance 1 is 2 / P00 by 2 / P11 centred at (P02 / P00, P12 / P11). */
    if (!(P[0] > 0) || !(P[5] > 0)) goto bad_proj;
    c.yfov = (float)(2.0 * atan(1.0 / P[5]));
    c.aspect = (float)(P[5] / P[0]);
    c.shift[0] = (float)((P[2] / P[0]) * P[5] / 2.0);
    c.shift[1] = (float)(P[6] / 2.0);
    /* P22 = -(f + n) / (f - n), P23 = -2 f n / (f - n); P22 = -1: no far plane. */
    if (P[10] != -1.0) {
      double n = P[11] / (P[10] - 1.0), f = P[11] / (P[10] + 1.0);
      c.znear = n > 0 && isfinite(n) ? (float)n : 0.0f;
      c.zfar = f > n && isfinite(f) ? (float)f : 0.0f;
    } else {
      double n = -P[11] / 2.0;
      c.znear = n > 0 ? (float)n : 0.0f;
    }
  } else {
    goto bad_proj;
  }
  *out = c;
  return 0;
singular:
  snprintf(err, err_cap, "camera: \"view\" has a degenerate or mirrored rotation");
  return -1;
bad_proj:
  snprintf(err, err_cap, "camera: \"projection\" is neither an OpenGL perspective (last row 0 0 -1 0) nor an "
           "orthographic (last row 0 0 0 1) projection with positive scales");
  return -1;
}

/* ---- replies --------------------------------------------------------------- */

size_t pb_serve_json_string(char *buf, size_t cap, const char *s) {
  size_t o = 0;
#define PUT(c)                 \
  do {                         \
    if (o + 1 >= cap) return 0; \
    buf[o++] = (c);            \
  } while (0)
  PUT('"');
  for (const unsigned char *p = (const unsigned char *)s; *p; ++p) {
    unsigned char c = *p;
    if (c == '"' || c == '\\') {
      PUT('\\');
      PUT((char)c);
    } else if (c < 0x20 || c == 0x7f) {
      if (o + 7 >= cap) return 0;
      o += (size_t)snprintf(buf + o, cap - o, "\\u%04x", c);
    } else if (c >= 0x80) {
      /* Replies are UTF-8: a byte that is not (a path from the file
       * system, say) becomes U+FFFD. */
      size_t n = utf8_len(p, strlen((const char *)p));
      if (!n) {
        if (o + 7 >= cap) return 0;
        memcpy(buf + o, "\\ufffd", 6), o += 6;
      } else {
        if (o + n + 1 >= cap) return 0;
        memcpy(buf + o, p, n), o += n, p += n - 1;
      }
    } else {
      PUT((char)c);
    }
  }
  PUT('"');
#undef PUT
  buf[o] = 0;
  return o;
}

typedef struct out {
  char *buf;
  size_t cap, len;
  int overflow;
} out;

static void add(out *o, const char *fmt, ...) {
  if (o->overflow) return;
  va_list ap;
  va_start(ap, fmt);
  int n = vsnprintf(o->buf + o->len, o->cap - o->len, fmt, ap);
  va_end(ap);
  if (n < 0 || (size_t)n >= o->cap - o->len) o->overflow = 1;
  else o->len += (size_t)n;
}

static void add_str(out *o, const char *s) {
  if (o->overflow) return;
  size_t n = pb_serve_json_string(o->buf + o->len, o->cap - o->len, s);
  if (!n) o->overflow = 1;
  else o->len += n;
}

static void add_head(out *o, const char *key, const char *cmd, const char *id, int ok) {
  add(o, "{\"%s\":", key);
  if (cmd) add_str(o, cmd);
  else add(o, "null");
  if (id && id[0]) add(o, ",\"id\":%s", id);
  add(o, ",\"ok\":%s", ok ? "true" : "false");
}

static size_t finish(out *o) {
  add(o, "}\n");
  return o->overflow ? 0 : o->len;
}

size_t pb_serve_format_ok(char *buf, size_t cap, const char *cmd, const char *id) {
  out o = {buf, cap, 0, 0};
  add_head(&o, "reply", cmd, id, 1);
  return finish(&o);
}

size_t pb_serve_format_error(char *buf, size_t cap, const char *cmd, const char *id, const char *message) {
  out o = {buf, cap, 0, 0};
  add_head(&o, "reply", cmd && cmd[0] ? cmd : NULL, id, 0);
  add(&o, ",\"error\":");
  add_str(&o, message);
  return finish(&o);
}

size_t pb_serve_format_frame(char *buf, size_t cap, const char *id, const pb_serve_frame_reply *f) {
  out o = {buf, cap, 0, 0};
  add_head(&o, f->requested ? "reply" : "event", "frame", f->requested ? id : NULL, 1);
  add(&o, ",\"frame\":%llu,\"path\":", (unsigned long long)f->frame);
  add_str(&o, f->path);
  add(&o, ",\"width\":%u,\"height\":%u,\"format\":", f->width, f->height);
  add_str(&o, f->format);
  add(&o, ",\"passes\":%u,\"still\":%s,\"render_ms\":%.3f,\"photons_stored\":%llu", f->passes,
      f->still ? "true" : "false", isfinite(f->render_ms) ? f->render_ms : 0.0, (unsigned long long)f->photons_stored);
  add(&o, ",\"tracer\":");
  add_str(&o, f->tracer ? f->tracer : "none");
  if (f->tracer && !strcmp(f->tracer, "images") && isfinite(f->image_miss_rate)) add(&o, ",\"image_miss_rate\":%.6g", f->image_miss_rate);
  if (f->has_noise) {
    if (f->noise >= 0 && isfinite(f->noise)) add(&o, ",\"noise\":%.6g", f->noise);
    else add(&o, ",\"noise\":null");
  }
  return finish(&o);
}
