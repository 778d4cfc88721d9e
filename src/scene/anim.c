/* Posing a loaded scene at a time t (glTF 2.0 node animation, spec Appendix
 * C): sample every channel, rebuild the affected world transforms with the
 * loader's own arithmetic (xform.h) and rewrite the vertices, normals,
 * cameras, lights and bounds that hang under animated nodes. See anim.h for
 * what the loader records. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "scene/anim.h"
#include "scene/deform.h"
#include "scene/scene.h"
#include "scene/tangents.h"

void pb_scene_anim_destroy(struct pb_scene_anim *a) {
  if (!a) return;
  for (uint32_t i = 0; i < a->sampler_count; ++i) {
    free(a->samplers[i].times);
    free(a->samplers[i].values);
  }
  free(a->samplers);
  free(a->channels);
  free(a->nodes);
  free(a->order);
  free(a->ranges);
  free(a->local_pos);
  free(a->local_nrm);
  free(a->camera_node);
  free(a->light_node);
  free(a->camera_frame);
  free(a->light_dir);
  free(a->trs);
  free(a->world);
  free(a->values);
  pb_deform_destroy(a->deform);
  free(a->deform);
  free(a->tan_given);
  free(a);
}

/* Element `e` (0: in-tangent, 1: value, 2: out-tangent for CUBICSPLINE) of
 * key k, component c. */
static double key(const pb_anim_sampler *S, uint32_t k, int e, int c) {
  if (S->interp == PB_ANIM_CUBICSPLINE) return S->values[((size_t)3 * k + (size_t)e) * (size_t)S->comps + (size_t)c];
  return S->values[(size_t)k * (size_t)S->comps + (size_t)c];
}

static void normalize4(double q[4]) {
  double l = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  if (l > 0 && isfinite(l))
    for (int c = 0; c < 4; ++c) q[c] /= l;
}

/* Spherical linear interpolation of unit quaternions along the shorter arc
 * (spec Appendix C: the sign of the dot product picks the arc). */
static void slerp(const double a_in[4], const double b_in[4], double u, double out[4]) {
  double a[4], b[4];
  memcpy(a, a_in, sizeof a);
  memcpy(b, b_in, sizeof b);
  normalize4(a);
  normalize4(b);
  double d = a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3];
  if (d < 0) {
    d = -d;
    for (int c = 0; c < 4; ++c) b[c] = -b[c];
  }
  double wa, wb;
  if (d > 0.9999995) { /* nearly equal: sin(theta) ~ 0, lerp is exact enough */
    wa = 1 - u;
    wb = u;
  } else {
    double th = acos(d), st = sin(th);
    wa = sin((1 - u) * th) / st;
    wb = sin(u * th) / st;
  }
  for (int c = 0; c < 4; ++c) out[c] = wa * a[c] + wb * b[c];
  normalize4(out);
}

/* The sampler's value at time t (S->comps values); outside its keys it holds
 * the first or last key's value (spec: clamp). */
static void sample(const pb_anim_sampler *S, int path, double t, double *out) {
  uint32_t n = S->key_count;
  int comps = S->comps;
  const float *T = S->times;
  if (n == 1 || !(t > T[0])) {
    for (int c = 0; c < comps; ++c) out[c] = key(S, 0, 1, c);
  } else if (t >= T[n - 1]) {
    for (int c = 0; c < comps; ++c) out[c] = key(S, n - 1, 1, c);
  } else {
    /* T[lo] <= t < T[hi], hi = lo + 1, so T[hi] - T[lo] > 0 even where the
     * file repeats a time (a jump: the later key wins from that time on). */
    uint32_t lo = 0, hi = n - 1;
    while (hi - lo > 1) {
      uint32_t mid = lo + (hi - lo) / 2;
      if ((double)T[mid] <= t) lo = mid;
      else hi = mid;
    }
    double td = (double)T[hi] - (double)T[lo], u = (t - (double)T[lo]) / td;
    if (S->interp == PB_ANIM_STEP) {
      for (int c = 0; c < comps; ++c) out[c] = key(S, lo, 1, c);
    } else if (S->interp == PB_ANIM_LINEAR) {
      if (path == PB_ANIM_ROTATION) {
        double a[4], b[4];
        for (int c = 0; c < 4; ++c) a[c] = key(S, lo, 1, c), b[c] = key(S, hi, 1, c);
        slerp(a, b, u, out);
      } else {
        for (int c = 0; c < comps; ++c) out[c] = (1 - u) * key(S, lo, 1, c) + u * key(S, hi, 1, c);
      }
    } else {
      /* Cubic Hermite: p = (2u^3 - 3u^2 + 1) v_k + td (u^3 - 2u^2 + u) b_k
       *                  + (-2u^3 + 3u^2) v_k+1 + td (u^3 - u^2) a_k+1 */
      double u2 = u * u, u3 = u2 * u;
      double h00 = 2 * u3 - 3 * u2 + 1, h10 = u3 - 2 * u2 + u, h01 = -2 * u3 + 3 * u2, h11 = u3 - u2;
      for (int c = 0; c < comps; ++c)
        out[c] = h00 * key(S, lo, 1, c) + td * h10 * key(S, lo, 2, c) + h01 * key(S, hi, 1, c) +
                 td * h11 * key(S, hi, 0, c);
    }
  }
  if (path == PB_ANIM_ROTATION) normalize4(out);
}

static void face_normal(const double a[3], const double b[3], const double c[3], double fn[3]) {
  double e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
  fn[0] = e1[1] * e2[2] - e1[2] * e2[1];
  fn[1] = e1[2] * e2[0] - e1[0] * e2[2];
  fn[2] = e1[0] * e2[1] - e1[1] * e2[0];
  if (!normalize3(fn)) fn[0] = 0, fn[1] = 0, fn[2] = 1; /* zero area: any unit normal */
}

static pb_result pose_range(pb_scene *s, const struct pb_scene_anim *a, const pb_anim_range *rg, double t) {
  const mat4 *M = &a->world[rg->node];
  const char *path = s->path ? s->path : "scene";
  if (rg->flat) {
    for (uint32_t k = 0; k < rg->tri_count; ++k) {
      const uint32_t *tri = s->triangles[rg->first_tri + k];
      double pw[3][3];
      for (int c = 0; c < 3; ++c) {
        const float *pl = a->local_pos[rg->local + (tri[c] - rg->first_vertex)];
        double p[3] = {pl[0], pl[1], pl[2]};
        xform_point(M, p, pw[c]);
        if (!fits_float3(pw[c]))
          return pb_fail(PB_ERR_SCENE_INVALID, "%s: animations: at t = %g nodes[%d] moves vertices out of float range",
                         path, t, rg->node);
      }
      double fn[3];
      face_normal(pw[0], pw[1], pw[2], fn);
      for (int c = 0; c < 3; ++c)
        for (int k2 = 0; k2 < 3; ++k2) s->positions[tri[c]][k2] = (float)pw[c][k2], s->normals[tri[c]][k2] = (float)fn[k2];
    }
    return PB_OK;
  }
  double N[9];
  normal_matrix(M, N);
  for (uint32_t i = 0; i < rg->vertex_count; ++i) {
    const float *pl = a->local_pos[rg->local + i], *nl = a->local_nrm[rg->local + i];
    double p[3] = {pl[0], pl[1], pl[2]}, pw[3], nw[3];
    xform_point(M, p, pw);
    if (!fits_float3(pw))
      return pb_fail(PB_ERR_SCENE_INVALID, "%s: animations: at t = %g nodes[%d] moves vertices out of float range", path,
                     t, rg->node);
    for (int r = 0; r < 3; ++r) nw[r] = N[r] * nl[0] + N[3 + r] * nl[1] + N[6 + r] * nl[2];
    if (!normalize3(nw)) nw[0] = nw[1] = nw[2] = 0; /* fixed below from the face */
    float *P = s->positions[rg->first_vertex + i], *Nn = s->normals[rg->first_vertex + i];
    for (int c = 0; c < 3; ++c) P[c] = (float)pw[c], Nn[c] = (float)nw[c];
  }
  /* As the loader does: a zero normal takes the face normal of the first
   * triangle that uses the vertex. */
  for (uint32_t k = 0; k < rg->tri_count; ++k) {
    const uint32_t *tri = s->triangles[rg->first_tri + k];
    for (int c = 0; c < 3; ++c) {
      float *Nn = s->normals[tri[c]];
      if (Nn[0] == 0 && Nn[1] == 0 && Nn[2] == 0) {
        double v[3][3], fn[3];
        for (int j = 0; j < 3; ++j)
          for (int k2 = 0; k2 < 3; ++k2) v[j][k2] = s->positions[tri[j]][k2];
        face_normal(v[0], v[1], v[2], fn);
        for (int k2 = 0; k2 < 3; ++k2) Nn[k2] = (float)fn[k2];
      }
    }
  }
  return PB_OK;
}

pb_result pb_scene_set_time(pb_scene *s, double t) {
  struct pb_scene_anim *a = s ? s->anim : NULL;
  if (!a) return PB_OK;
  const char *path = s->path ? s->path : "scene";
  if (isnan(t)) return pb_fail(PB_ERR_USAGE, "%s: animations: time is NaN", path);
  /* Clamp to the animation range (each sampler also holds its own first and
   * last keys, so this only makes the contract explicit). */
  if (t < s->anim_start) t = s->anim_start;
  if (t > s->anim_end) t = s->anim_end;

  /* Local TRS per node: the file's, with each animated component replaced. */
  for (uint32_t n = 0; n < a->node_count; ++n) {
    const pb_anim_node *nd = &a->nodes[n];
    double *x = a->trs[n];
    memcpy(x, nd->t, sizeof nd->t);
    memcpy(x + 3, nd->r, sizeof nd->r);
    memcpy(x + 7, nd->s, sizeof nd->s);
  }
  for (uint32_t i = 0; i < a->channel_count; ++i) {
    const pb_anim_channel *ch = &a->channels[i];
    const pb_anim_sampler *S = &a->samplers[ch->sampler];
    double *v = a->values;
    sample(S, ch->path, t, v);
    if (ch->path == PB_ANIM_WEIGHTS) { /* the node's morph weights (deform.h) */
      pb_deform *d = a->deform;
      if (d && d->node_weights[ch->node] != UINT32_MAX)
        for (int k = 0; k < S->comps; ++k) d->weights[d->node_weights[ch->node] + (uint32_t)k] = (float)v[k];
      continue;
    }
    double *x = a->trs[ch->node] + (ch->path == PB_ANIM_TRANSLATION ? 0 : ch->path == PB_ANIM_ROTATION ? 3 : 7);
    memcpy(x, v, (ch->path == PB_ANIM_ROTATION ? 4 : 3) * sizeof *v);
  }
  /* World transforms in the loader's order and arithmetic: the roots' parent
   * is the precision origin's translation (scene.h, pb_scene.origin). */
  mat4 I;
  memset(&I, 0, sizeof I);
  I.m[0] = I.m[5] = I.m[10] = I.m[15] = 1;
  I.m[12] = -s->origin[0], I.m[13] = -s->origin[1], I.m[14] = -s->origin[2];
  for (uint32_t i = 0; i < a->order_count; ++i) {
    int32_t n = a->order[i];
    const pb_anim_node *nd = &a->nodes[n];
    mat4 local = nd->has_matrix ? nd->matrix : trs_matrix(a->trs[n], a->trs[n] + 3, a->trs[n] + 7);
    a->world[n] = mat_mul(nd->parent >= 0 ? &a->world[nd->parent] : &I, &local);
    if (!finite_mat(&a->world[n]))
      return pb_fail(PB_ERR_SCENE_INVALID, "%s: animations: at t = %g the transform of nodes[%d] is not finite", path, t, n);
  }
  pb_result r;
  for (uint32_t i = 0; i < a->range_count; ++i)
    if ((r = pose_range(s, a, &a->ranges[i], t)) != PB_OK) return r;
  if (a->deform) {
    pb_skins_update(a->deform, a->world);
    for (uint32_t i = 0; i < a->deform->range_count; ++i) {
      const pb_deform_range *dr = &a->deform->ranges[i];
      if (dr->dynamic && (r = pb_deform_pose(s, a->deform, dr, a->world, s->tangents, t)) != PB_OK) return r;
    }
  }

  for (uint32_t i = 0; i < s->camera_count; ++i) {
    int32_t n = a->camera_node[i];
    if (n < 0 || !a->nodes[n].animated) continue;
    const mat4 *M = &a->world[n];
    pb_camera *cam = &s->cameras[i];
    double o[3] = {0, 0, 0}, pos[3], f[3], u[3], fz[3] = {0, 0, -1}, uy[3] = {0, 1, 0};
    xform_point(M, o, pos);
    xform_dir(M, fz, f);
    xform_dir(M, uy, u);
    if (!fits_float3(pos))
      return pb_fail(PB_ERR_SCENE_INVALID, "%s: animations: at t = %g nodes[%d] moves its camera out of float range", path, t, n);
    for (int k = 0; k < 3; ++k) cam->position[k] = (float)pos[k];
    int ok = normalize3(f);
    if (ok) {
      double dp = u[0] * f[0] + u[1] * f[1] + u[2] * f[2];
      for (int k = 0; k < 3; ++k) u[k] -= dp * f[k];
      ok = normalize3(u);
    }
    if (!ok) { /* degenerate pose (scale 0): keep the rest orientation */
      memcpy(cam->forward, a->camera_frame[i], sizeof cam->forward);
      memcpy(cam->up, a->camera_frame[i] + 3, sizeof cam->up);
      memcpy(cam->right, a->camera_frame[i] + 6, sizeof cam->right);
      continue;
    }
    for (int k = 0; k < 3; ++k) cam->forward[k] = (float)f[k], cam->up[k] = (float)u[k];
    cam->right[0] = (float)(f[1] * u[2] - f[2] * u[1]);
    cam->right[1] = (float)(f[2] * u[0] - f[0] * u[2]);
    cam->right[2] = (float)(f[0] * u[1] - f[1] * u[0]);
  }
  for (uint32_t i = 0; i < s->light_count; ++i) {
    int32_t n = a->light_node[i];
    if (n < 0 || !a->nodes[n].animated) continue;
    const mat4 *M = &a->world[n];
    /* Position, and the axes its kind has (scene/light.h); a degenerate
     * pose keeps the loaded direction. */
    if (!pb_light_pose(&s->lights[i], M, a->light_dir[i]))
      return pb_fail(PB_ERR_SCENE_INVALID, "%s: animations: at t = %g nodes[%d] moves its light out of float range", path, t, n);
  }
  pb_scene_update_bounds(s);
  /* Normal maps: the tangent frames follow the posed vertices. They are
   * generated from the uvs (tangents.c) at every pose, also where the file
   * gave TANGENT to a rigidly moving node (its rest-pose values would need
   * their node transforms, which only the loader holds); the rest pose keeps
   * the file's, and skinned or morphed vertices keep theirs, which the
   * deformation posed above (tan_given). */
  if (s->tangents && s->uvs)
    return pb_tangents_generate((const float(*)[3])s->positions, (const float(*)[3])s->normals,
                                (const float(*)[2])s->uvs, s->vertex_count, (const uint32_t(*)[3])s->triangles,
                                s->triangle_count, a->tan_given, s->tangents);
  return PB_OK;
}
