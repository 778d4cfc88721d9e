/* Shader contract test: the Binding and SpecId decorations of every embedded
 * SPIR-V module (read as test_gpu_layout reads the struct offsets) equal the
 * numbers of shaders/shared/pb_contract.h that the host binds and
 * specializes with; every binding a module declares is one the contract
 * names for that kernel and lies below the kernel's binding count. GPU-free.
 * A kernel that declares a buffer at a number its C side does not know, or
 * a header that renumbers one side only, fails here instead of rendering
 * garbage. */
#include <stddef.h>
#include <string.h>

#include "pbtest.h"
#include "shared/pb_gpu.h"

#include "shaders/atrous.spv.h"
#include "shaders/gbuffer_rq.spv.h"
#include "shaders/gbuffer_rq_blender.spv.h"
#include "shaders/direct_rq.spv.h"
#include "shaders/direct_rq_blender.spv.h"
#include "shaders/gather_rq.spv.h"
#include "shaders/gather_rq_blender.spv.h"
#include "shaders/gather_upsample_rq.spv.h"
#include "shaders/gather_upsample_rq_blender.spv.h"
#include "shaders/knn_rq.spv.h"
#include "shaders/knn_rq_blender.spv.h"
#include "shaders/photon_trace_rq.spv.h"
#include "shaders/photon_trace_rq_blender.spv.h"
#include "shaders/image_maps_rq.spv.h"
#include "shaders/photon_rsm_rq.spv.h"
#include "shaders/photon_rsm_rq_blender.spv.h"
#include "shaders/motion_rq.spv.h"
#include "shaders/vsch_leaf_rq.spv.h"
#include "shaders/vsch_shade_rq.spv.h"
#include "shaders/vsch_shade_rq_blender.spv.h"
#include "shaders/direct.spv.h"
#include "shaders/direct_blender.spv.h"
#include "shaders/gather.spv.h"
#include "shaders/gather_blender.spv.h"
#include "shaders/gather_upsample.spv.h"
#include "shaders/gather_upsample_blender.spv.h"
#include "shaders/upsample_compose.spv.h"
#include "shaders/upsample_mark.spv.h"
#include "shaders/knn.spv.h"
#include "shaders/knn_blender.spv.h"
#include "shaders/gbuffer.spv.h"
#include "shaders/gbuffer_blender.spv.h"
#include "shaders/lbvh_bounds.spv.h"
#include "shaders/lbvh_climb.spv.h"
#include "shaders/lbvh_morton.spv.h"
#include "shaders/lbvh_setup.spv.h"
#include "shaders/lbvh_sort_downsweep.spv.h"
#include "shaders/lbvh_sort_downsweep_serial.spv.h"
#include "shaders/lbvh_sort_downsweep_sg.spv.h"
#include "shaders/lbvh_sort_setup.spv.h"
#include "shaders/lbvh_sort_spine.spv.h"
#include "shaders/lbvh_sort_upsweep.spv.h"
#include "shaders/lbvh_sort_upsweep_serial.spv.h"
#include "shaders/motion.spv.h"
#include "shaders/raycast_rq.spv.h"
#include "shaders/photon_rsm.spv.h"
#include "shaders/photon_rsm_blender.spv.h"
#include "shaders/photon_trace.spv.h"
#include "shaders/photon_trace_blender.spv.h"
#include "shaders/photon_trace_images.spv.h"
#include "shaders/photon_trace_images_blender.spv.h"
#include "shaders/image_maps.spv.h"
#include "shaders/image_maps_query.spv.h"
#include "shaders/raycast.spv.h"
#include "shaders/resolve.spv.h"
#include "shaders/present.spv.h"
#include "shaders/temporal.spv.h"
#include "shaders/filter_io.spv.h"
#include "shaders/shading_correction.spv.h"
#include "shaders/splat_count.spv.h"
#include "shaders/splat_resolve.spv.h"
#include "shaders/splat_resolve_blender.spv.h"
#include "shaders/splat_splat.spv.h"
#include "shaders/vsch_blur.spv.h"
#include "shaders/vsch_clear.spv.h"
#include "shaders/vsch_cone.spv.h"
#include "shaders/vsch_count.spv.h"
#include "shaders/vsch_fill.spv.h"
#include "shaders/vsch_leaf.spv.h"
#include "shaders/vsch_mark.spv.h"
#include "shaders/vsch_range.spv.h"
#include "shaders/vsch_ranges.spv.h"
#include "shaders/vsch_scan.spv.h"
#include "shaders/vsch_shade.spv.h"
#include "shaders/vsch_shade_blender.spv.h"
#include "shaders/vsch_up.spv.h"

typedef struct entry {
  const char *name; /* block type name (bindings) or constant name (SpecId) */
  long value;
} entry;
#define END {NULL, 0}

/* The scene's buffers (common/scene.glsl) every scene-reading kernel shares. */
#define SCENE_COMMON                                                                                        \
  {"FrameBuf", PB_BIND_FRAME}, {"Nodes", PB_BIND_NODES}, {"pb_tlas", PB_BIND_NODES}, {"Tris", PB_BIND_TRIS}, {"Indices", PB_BIND_INDICES}, \
      {"Normals", PB_BIND_NORMALS}, {"Uvs", PB_BIND_UVS}, {"TriMat", PB_BIND_TRI_MATERIAL},                  \
      {"Materials", PB_BIND_MATERIALS}, {"Textures", PB_BIND_TEXTURES}, {"Texels", PB_BIND_TEXELS},         \
      {"Lights", PB_BIND_LIGHTS}, {"Positions", PB_BIND_POSITIONS}, {"Emitters", PB_BIND_EMITTERS}
#define SCENE_SPEC                                                                                         \
  {"SC_HAS_NORMALS", PB_SPEC_HAS_NORMALS}, {"SC_TEXTURES", PB_SPEC_TEXTURES}, {"SC_SPECULAR", PB_SPEC_SPECULAR}, \
      {"SC_EMISSIVE", PB_SPEC_EMISSIVE}, {"SC_SOFT_LIGHTS", PB_SPEC_SOFT_LIGHTS}, {"SC_WORLD", PB_SPEC_WORLD},   \
      {"SC_ALPHA", PB_SPEC_ALPHA}, {"SC_PRINCIPLED2", PB_SPEC_PRINCIPLED2}, {"SC_CLOSURES", PB_SPEC_CLOSURES}

static const entry scene_pass[] = {SCENE_COMMON, {"GBuf", PB_BIND_GBUFFER}, {"Accum", PB_BIND_ACCUM},
                                   {"WorldBuf", PB_BIND_WORLD}, END};
static const entry scene_spec[] = {SCENE_SPEC, END};
static const entry gather_bind[] = {SCENE_COMMON,
                                    {"GBuf", PB_BIND_GBUFFER},
                                    {"Accum", PB_BIND_ACCUM},
                                    {"Photons", PB_GATHER_BIND_PHOTONS},
                                    {"Nodes2", PB_GATHER_BIND_NODES},
                                    {"InfoBuf", PB_GATHER_BIND_INFO},
                                    {"PhotonAccum", PB_GATHER_BIND_ACCUM},
                                    {"PhotonNmap", PB_GATHER_BIND_NMAP},
                                    END};
static const entry gather_ups_bind[] = {SCENE_COMMON,
                                        {"GBuf", PB_BIND_GBUFFER},
                                        {"Accum", PB_BIND_ACCUM},
                                        {"Photons", PB_GATHER_BIND_PHOTONS},
                                        {"Nodes2", PB_GATHER_BIND_NODES},
                                        {"InfoBuf", PB_GATHER_BIND_INFO},
                                        {"PhotonAccum", PB_GATHER_BIND_ACCUM},
                                        {"PhotonNmap", PB_GATHER_BIND_NMAP},
                                        {"UpsIrr", PB_GATHER_BIND_UPS_IRR},
                                        {"UpsList", PB_GATHER_BIND_UPS_LIST},
                                        END};
static const entry ups_bind[] = {SCENE_COMMON,
                                 {"GBuf", PB_BIND_GBUFFER},
                                 {"Accum", PB_BIND_ACCUM},
                                 {"UpsIrr", PB_UPS_BIND_IRR},
                                 {"UpsList", PB_UPS_BIND_LIST},
                                 {"PhotonAccum", PB_UPS_BIND_PACCUM},
                                 END};
static const entry gather_spec[] = {SCENE_SPEC, {"SC_NORMAL_MAPS", PB_SPEC_NORMAL_MAPS}, END};
static const entry knn_bind[] = {SCENE_COMMON,
                                 {"GBuf", PB_BIND_GBUFFER},
                                 {"Accum", PB_BIND_ACCUM},
                                 {"Photons", PB_KNN_BIND_PHOTONS},
                                 {"Nodes2", PB_KNN_BIND_NODES},
                                 {"InfoBuf", PB_KNN_BIND_INFO},
                                 {"PhotonAccum", PB_KNN_BIND_ACCUM},
                                 {"PhotonNmap", PB_KNN_BIND_NMAP},
                                 END};
static const entry knn_spec[] = {SCENE_SPEC, {"SC_NORMAL_MAPS", PB_SPEC_NORMAL_MAPS}, {"SC_K", PB_SPEC_KNN_K},
                                 {"SC_BUDGET", PB_SPEC_KNN_BUDGET}, END};
static const entry trace_bind[] = {SCENE_COMMON,
                                   {"Photons", PB_PHOTON_BIND_PHOTONS},
                                   {"Counts", PB_PHOTON_BIND_COUNTS},
                                   {"Params", PB_PHOTON_BIND_PARAMS},
                                   {"RsmLights", PB_PHOTON_BIND_RSM_LIGHTS},
                                   {"RsmTexels", PB_PHOTON_BIND_RSM_TEXELS},
                                   {"WorldBuf", PB_PHOTON_BIND_WORLD},
                                   END};
static const entry trace_spec[] = {SCENE_SPEC, {"SC_TRANSMISSION", PB_SPEC_TRANSMISSION}, END};
static const entry rsm_bind[] = {SCENE_COMMON, {"RsmLights", PB_RSM_BIND_LIGHTS}, {"RsmTexels", PB_RSM_BIND_TEXELS},
                                 END};
static const entry lbvh_bind[] = {{"InfoBuf", PB_LBVH_BIND_INFO},
                                  {"PhotonsIn", PB_LBVH_BIND_PHOTONS_IN},
                                  {"MapCounts", PB_LBVH_BIND_MAP_COUNTS},
                                  {"PhotonsSorted", PB_LBVH_BIND_SORTED},
                                  {"Keys", PB_LBVH_BIND_KEYS},
                                  {"Vals", PB_LBVH_BIND_VALS},
                                  {"Nodes", PB_LBVH_BIND_NODES},
                                  {"Visit", PB_LBVH_BIND_VISIT},
                                  {"Partial", PB_LBVH_BIND_PARTIAL},
                                  {"PhotonsIn4", PB_LBVH_BIND_PHOTONS_IN4},
                                  {"PhotonsSorted4", PB_LBVH_BIND_SORTED4},
                                  {"Nodes4", PB_LBVH_BIND_NODES4},
                                  END};
static const entry climb_spec[] = {{"SC_FENCES", PB_SPEC_FENCES}, END};
static const entry sort_bind[] = {{"SortState", PB_SORT_BIND_STATE}, {"SortKeys", PB_SORT_BIND_KEYS},
                                  {"SortVals", PB_SORT_BIND_VALS},   {"SortHist", PB_SORT_BIND_HIST},
                                  {"SortCount", PB_SORT_BIND_COUNT_SRC}, {"SortKeys4", PB_SORT_BIND_KEYS4},
                                  {"SortVals4", PB_SORT_BIND_VALS4}, END};
static const entry atrous_bind[] = {{"S", PB_ATROUS_BIND_S},           {"Detail", PB_ATROUS_BIND_DETAIL},
                                    {"Geo", PB_ATROUS_BIND_GEO},       {"Indirect", PB_ATROUS_BIND_INDIRECT},
                                    {"Albedo", PB_ATROUS_BIND_ALBEDO}, END};
static const entry temporal_bind[] = {{"HistIn", PB_TEMPORAL_BIND_HIST_IN},     {"GeoPrev", PB_TEMPORAL_BIND_GEO_PREV},
                                      {"GeoCur", PB_TEMPORAL_BIND_GEO},         {"Indirect", PB_TEMPORAL_BIND_INDIRECT},
                                      {"Albedo", PB_TEMPORAL_BIND_ALBEDO},      {"Motion", PB_TEMPORAL_BIND_MOTION},
                                      {"HistOut", PB_TEMPORAL_BIND_HIST_OUT},   {"Result", PB_TEMPORAL_BIND_RESULT},
                                      {"Stats", PB_TEMPORAL_BIND_STATS}, END};
static const entry filter_io_bind[] = {{"Planes", PB_FILTER_IO_BIND_PLANES},
                                       {"PhotonPlanes", PB_FILTER_IO_BIND_PHOTON_PLANES},
                                       {"Geo", PB_FILTER_IO_BIND_GEO},
                                       {"Albedo", PB_FILTER_IO_BIND_ALBEDO},
                                       {"IndirectIn", PB_FILTER_IO_BIND_INDIRECT_IN},
                                       {"Indirect", PB_FILTER_IO_BIND_INDIRECT},
                                       {"CausticIn", PB_FILTER_IO_BIND_CAUSTIC_IN},
                                       {"Caustic", PB_FILTER_IO_BIND_CAUSTIC},
                                       {"Guard", PB_FILTER_IO_BIND_GUARD},
                                       END};
static const entry shading_bind[] = {{"Planes", PB_SHADING_BIND_PLANES},
                                     {"PhotonPlanes", PB_SHADING_BIND_PHOTON_PLANES}, END};
static const entry motion_bind[] = {{"Nodes", PB_MOTION_BIND_NODES}, {"pb_tlas", PB_MOTION_BIND_NODES},
                                    {"Tris", PB_MOTION_BIND_TRIS},
                                    {"Indices", PB_MOTION_BIND_INDICES},
                                    {"PrevPos", PB_MOTION_BIND_PREV_POSITIONS},
                                    {"Params", PB_MOTION_BIND_PARAMS},
                                    {"Motion", PB_MOTION_BIND_MOTION},
                                    END};
static const entry raycast_bind[] = {{"Nodes", PB_RAYCAST_BIND_NODES}, {"Tris", PB_RAYCAST_BIND_TRIS},
                                     {"Rays", PB_RAYCAST_BIND_RAYS},   {"Hits", PB_RAYCAST_BIND_HITS}, END};
/* An acceleration structure has no block: the variable's own name. */
static const entry raycast_rq_bind[] = {{"Tlas", PB_RAYCAST_RQ_BIND_TLAS}, {"Rays", PB_RAYCAST_RQ_BIND_RAYS},
                                        {"Hits", PB_RAYCAST_RQ_BIND_HITS}, END};
static const entry resolve_bind[] = {{"Accum", PB_RESOLVE_BIND_ACCUM},
                                     {"PhotonAccum", PB_RESOLVE_BIND_PHOTON_ACCUM},
                                     {"PhotonNmap", PB_RESOLVE_BIND_NMAP},
                                     {"Planes", PB_RESOLVE_BIND_OUT},
                                     {"Guard", PB_RESOLVE_BIND_GUARD},
                                     {"PhotonPlanes", PB_RESOLVE_BIND_OUT_PHOTONS},
                                     {"KpdSums", PB_RESOLVE_BIND_KPD_SUMS},
                                     END};
static const entry trace_images_bind[] = {SCENE_COMMON,
                                          {"Photons", PB_PHOTON_BIND_PHOTONS},
                                          {"Counts", PB_PHOTON_BIND_COUNTS},
                                          {"Params", PB_PHOTON_BIND_PARAMS},
                                          {"RsmLights", PB_PHOTON_BIND_RSM_LIGHTS},
                                          {"RsmTexels", PB_PHOTON_BIND_RSM_TEXELS},
                                          {"WorldBuf", PB_PHOTON_BIND_WORLD},
                                          {"ImageMaps", PB_PHOTON_BIND_IMAGE_MAPS},
                                          {"ImageTexels", PB_PHOTON_BIND_IMAGE_TEXELS},
                                          {"ImageCounts", PB_PHOTON_BIND_IMAGE_COUNTS},
                                          END};
static const entry image_bind[] = {{"Nodes", PB_IMAGE_BIND_NODES}, {"pb_tlas", PB_IMAGE_BIND_NODES},     {"Tris", PB_IMAGE_BIND_TRIS},
                                   {"Indices", PB_IMAGE_BIND_INDICES}, {"Positions", PB_IMAGE_BIND_POSITIONS},
                                   {"TriMat", PB_IMAGE_BIND_TRI_MATERIAL}, {"Maps", PB_IMAGE_BIND_MAPS},
                                   {"Texels", PB_IMAGE_BIND_TEXELS},   {"Rays", PB_IMAGE_BIND_RAYS},
                                   {"Hits", PB_IMAGE_BIND_HITS},       {"Counts", PB_IMAGE_BIND_COUNTS}, END};
static const entry present_bind[] = {{"Lut", PB_PRESENT_BIND_LUT},
                                     {"Src", PB_PRESENT_BIND_IN},
                                     {"Dst", PB_PRESENT_BIND_OUT},
                                     END};
static const entry vsch_bind[] = {{"FrameBuf", PB_VSCH_BIND_FRAME}, {"GBuf", PB_VSCH_BIND_GBUFFER},
                                  {"VschData", PB_VSCH_BIND_DATA},   {"Photons", PB_VSCH_BIND_PHOTONS},
                                  {"Counts", PB_VSCH_BIND_COUNTS},   {"Keys", PB_VSCH_BIND_KEYS},
                                  {"Vals", PB_VSCH_BIND_VALS},       END};
static const entry vsch_shade_bind[] = {SCENE_COMMON,
                                        {"GBuf", PB_BIND_GBUFFER},
                                        {"Accum", PB_BIND_ACCUM},
                                        {"VschData", PB_VSCH_SHADE_BIND_DATA},
                                        {"Photons", PB_VSCH_SHADE_BIND_PHOTONS},
                                        {"Vals", PB_VSCH_SHADE_BIND_VALS},
                                        {"PhotonAccum", PB_VSCH_SHADE_BIND_ACCUM},
                                        {"PhotonNmap", PB_VSCH_SHADE_BIND_NMAP},
                                        END};
static const entry no_spec[] = {END};
/* The splatting passes (seed 001 24.3): count and splat read the frame and
 * the G-buffer of the scene's set, the resolve shades with all of it. */
#define SPLAT_OWN                                                                                          \
  {"Photons", PB_SPLAT_BIND_PHOTONS}, {"MapCounts", PB_SPLAT_BIND_COUNTS}, {"Tiles", PB_SPLAT_BIND_TILES}, \
      {"Stats", PB_SPLAT_BIND_STATS}
static const entry splat_bind[] = {{"FrameBuf", PB_BIND_FRAME}, {"GBuf", PB_BIND_GBUFFER}, {"Target", PB_SPLAT_BIND_TARGET},
                                   SPLAT_OWN, END};
static const entry splat_resolve_bind[] = {SCENE_COMMON,
                                           {"GBuf", PB_BIND_GBUFFER},
                                           {"Accum", PB_BIND_ACCUM},
                                           {"Tiles", PB_SPLAT_BIND_TILES},
                                           {"Target", PB_SPLAT_BIND_TARGET},
                                           {"PhotonAccum", PB_SPLAT_BIND_ACCUM},
                                           {"PhotonNmap", PB_SPLAT_BIND_NMAP},
                                           END};

typedef struct module {
  const char *name;
  const uint32_t *words;
  size_t bytes;
  const entry *bind, *spec;
  uint32_t bind_count; /* the pipeline's binding_count */
} module;
#define MOD(n, b, s, c) {#n, pb_spv_##n, sizeof pb_spv_##n, b, s, c}

static const module modules[] = {
    MOD(gbuffer, scene_pass, scene_spec, PB_BIND_COUNT),
    MOD(gbuffer_blender, scene_pass, scene_spec, PB_BIND_COUNT),
    MOD(gbuffer_rq, scene_pass, scene_spec, PB_BIND_COUNT),
    MOD(gbuffer_rq_blender, scene_pass, scene_spec, PB_BIND_COUNT),
    MOD(direct, scene_pass, scene_spec, PB_BIND_COUNT),
    MOD(direct_blender, scene_pass, scene_spec, PB_BIND_COUNT),
    MOD(direct_rq, scene_pass, scene_spec, PB_BIND_COUNT),
    MOD(direct_rq_blender, scene_pass, scene_spec, PB_BIND_COUNT),
    MOD(gather, gather_bind, gather_spec, PB_GATHER_BIND_COUNT),
    MOD(gather_blender, gather_bind, gather_spec, PB_GATHER_BIND_COUNT),
    MOD(gather_rq, gather_bind, gather_spec, PB_GATHER_BIND_COUNT),
    MOD(gather_rq_blender, gather_bind, gather_spec, PB_GATHER_BIND_COUNT),
    MOD(gather_upsample, gather_ups_bind, gather_spec, PB_GATHER_UPS_BIND_COUNT),
    MOD(gather_upsample_blender, gather_ups_bind, gather_spec, PB_GATHER_UPS_BIND_COUNT),
    MOD(gather_upsample_rq, gather_ups_bind, gather_spec, PB_GATHER_UPS_BIND_COUNT),
    MOD(gather_upsample_rq_blender, gather_ups_bind, gather_spec, PB_GATHER_UPS_BIND_COUNT),
    MOD(upsample_mark, ups_bind, scene_spec, PB_UPS_BIND_COUNT),
    MOD(upsample_compose, ups_bind, scene_spec, PB_UPS_BIND_COUNT),
    MOD(knn, knn_bind, knn_spec, PB_KNN_BIND_COUNT),
    MOD(knn_blender, knn_bind, knn_spec, PB_KNN_BIND_COUNT),
    MOD(knn_rq, knn_bind, knn_spec, PB_KNN_BIND_COUNT),
    MOD(knn_rq_blender, knn_bind, knn_spec, PB_KNN_BIND_COUNT),
    MOD(photon_trace, trace_bind, trace_spec, PB_PHOTON_BIND_COUNT),
    MOD(photon_trace_blender, trace_bind, trace_spec, PB_PHOTON_BIND_COUNT),
    MOD(photon_trace_rq, trace_bind, trace_spec, PB_PHOTON_BIND_COUNT),
    MOD(photon_trace_rq_blender, trace_bind, trace_spec, PB_PHOTON_BIND_COUNT),
    MOD(photon_trace_images, trace_images_bind, trace_spec, PB_PHOTON_IMAGES_BIND_COUNT),
    MOD(photon_trace_images_blender, trace_images_bind, trace_spec, PB_PHOTON_IMAGES_BIND_COUNT),
    MOD(image_maps, image_bind, no_spec, PB_IMAGE_BIND_COUNT),
    MOD(image_maps_rq, image_bind, no_spec, PB_IMAGE_BIND_COUNT),
    MOD(image_maps_query, image_bind, no_spec, PB_IMAGE_BIND_COUNT),
    MOD(photon_rsm, rsm_bind, scene_spec, PB_RSM_BIND_COUNT),
    MOD(photon_rsm_blender, rsm_bind, scene_spec, PB_RSM_BIND_COUNT),
    MOD(photon_rsm_rq, rsm_bind, scene_spec, PB_RSM_BIND_COUNT),
    MOD(photon_rsm_rq_blender, rsm_bind, scene_spec, PB_RSM_BIND_COUNT),
    MOD(lbvh_setup, lbvh_bind, no_spec, PB_LBVH_BIND_COUNT),
    MOD(lbvh_bounds, lbvh_bind, no_spec, PB_LBVH_BIND_COUNT),
    MOD(lbvh_morton, lbvh_bind, no_spec, PB_LBVH_BIND_COUNT),
    MOD(lbvh_climb, lbvh_bind, climb_spec, PB_LBVH_BIND_COUNT),
    MOD(lbvh_sort_setup, sort_bind, no_spec, PB_SORT_BIND_COUNT),
    MOD(lbvh_sort_upsweep, sort_bind, no_spec, PB_SORT_BIND_COUNT),
    MOD(lbvh_sort_upsweep_serial, sort_bind, no_spec, PB_SORT_BIND_COUNT),
    MOD(lbvh_sort_spine, sort_bind, no_spec, PB_SORT_BIND_COUNT),
    MOD(lbvh_sort_downsweep, sort_bind, no_spec, PB_SORT_BIND_COUNT),
    MOD(lbvh_sort_downsweep_serial, sort_bind, no_spec, PB_SORT_BIND_COUNT),
    MOD(lbvh_sort_downsweep_sg, sort_bind, no_spec, PB_SORT_BIND_COUNT),
    MOD(atrous, atrous_bind, no_spec, PB_ATROUS_BIND_COUNT),
    MOD(temporal, temporal_bind, no_spec, PB_TEMPORAL_BIND_COUNT),
    MOD(motion, motion_bind, no_spec, PB_MOTION_BIND_COUNT),
    MOD(motion_rq, motion_bind, no_spec, PB_MOTION_BIND_COUNT),
    MOD(raycast, raycast_bind, no_spec, PB_RAYCAST_BIND_COUNT),
    MOD(raycast_rq, raycast_rq_bind, no_spec, PB_RAYCAST_RQ_BIND_COUNT),
    MOD(resolve, resolve_bind, no_spec, PB_RESOLVE_BIND_COUNT),
    MOD(filter_io, filter_io_bind, no_spec, PB_FILTER_IO_BIND_COUNT),
    MOD(shading_correction, shading_bind, no_spec, PB_SHADING_BIND_COUNT),
    MOD(splat_count, splat_bind, no_spec, PB_SPLAT_BIND_COUNT),
    MOD(splat_splat, splat_bind, no_spec, PB_SPLAT_BIND_COUNT),
    MOD(splat_resolve, splat_resolve_bind, gather_spec, PB_SPLAT_BIND_COUNT),
    MOD(splat_resolve_blender, splat_resolve_bind, gather_spec, PB_SPLAT_BIND_COUNT),
    MOD(present, present_bind, no_spec, PB_PRESENT_BIND_COUNT),
    MOD(vsch_clear, vsch_bind, no_spec, PB_VSCH_BIND_COUNT),
    MOD(vsch_range, vsch_bind, no_spec, PB_VSCH_BIND_COUNT),
    MOD(vsch_mark, vsch_bind, no_spec, PB_VSCH_BIND_COUNT),
    MOD(vsch_scan, vsch_bind, no_spec, PB_VSCH_BIND_COUNT),
    MOD(vsch_cone, vsch_bind, no_spec, PB_VSCH_BIND_COUNT),
    MOD(vsch_up, vsch_bind, no_spec, PB_VSCH_BIND_COUNT),
    MOD(vsch_count, vsch_bind, no_spec, PB_VSCH_BIND_COUNT),
    MOD(vsch_fill, vsch_bind, no_spec, PB_VSCH_BIND_COUNT),
    MOD(vsch_ranges, vsch_bind, no_spec, PB_VSCH_BIND_COUNT),
    MOD(vsch_leaf, vsch_shade_bind, gather_spec, PB_VSCH_SHADE_BIND_COUNT),
    MOD(vsch_leaf_rq, vsch_shade_bind, gather_spec, PB_VSCH_SHADE_BIND_COUNT),
    MOD(vsch_shade, vsch_shade_bind, gather_spec, PB_VSCH_SHADE_BIND_COUNT),
    MOD(vsch_shade_blender, vsch_shade_bind, gather_spec, PB_VSCH_SHADE_BIND_COUNT),
    MOD(vsch_shade_rq, vsch_shade_bind, gather_spec, PB_VSCH_SHADE_BIND_COUNT),
    MOD(vsch_shade_rq_blender, vsch_shade_bind, gather_spec, PB_VSCH_SHADE_BIND_COUNT),
    MOD(vsch_blur, vsch_shade_bind, gather_spec, PB_VSCH_SHADE_BIND_COUNT),
};

enum { OP_NAME = 5, OP_TYPE_POINTER = 32, OP_VARIABLE = 59, OP_DECORATE = 71, DEC_SPEC_ID = 1, DEC_BINDING = 33 };

/* The OpName of id, or NULL. */
static const char *name_of(const uint32_t *w, size_t n, uint32_t id) {
  for (size_t i = 5; i < n;) {
    uint32_t op = w[i] & 0xffff, len = w[i] >> 16;
    if (len == 0) break;
    if (op == OP_NAME && w[i + 1] == id) return (const char *)&w[i + 2];
    i += len;
  }
  return NULL;
}

/* The type a variable points at (its block), or 0. */
static uint32_t pointee_of_variable(const uint32_t *w, size_t n, uint32_t var) {
  uint32_t ptr = 0;
  for (size_t i = 5; i < n;) {
    uint32_t op = w[i] & 0xffff, len = w[i] >> 16;
    if (len == 0) break;
    if (op == OP_VARIABLE && w[i + 2] == var) ptr = w[i + 1];
    i += len;
  }
  for (size_t i = 5; ptr && i < n;) {
    uint32_t op = w[i] & 0xffff, len = w[i] >> 16;
    if (len == 0) break;
    if (op == OP_TYPE_POINTER && w[i + 1] == ptr) return w[i + 3];
    i += len;
  }
  return 0;
}

static long lookup(const entry *e, const char *name) {
  for (; e->name; ++e)
    if (name && strcmp(e->name, name) == 0) return e->value;
  return -1;
}

int main(void) {
  for (size_t m = 0; m < sizeof modules / sizeof *modules; ++m) {
    const module *md = &modules[m];
    const uint32_t *w = md->words;
    size_t n = md->bytes / 4;
    CHECK(n > 5 && w[0] == 0x07230203u);
    int bindings = 0;
    for (size_t i = 5; i < n;) {
      uint32_t op = w[i] & 0xffff, len = w[i] >> 16;
      if (len == 0) break;
      if (op == OP_DECORATE && w[i + 2] == DEC_BINDING) {
        const char *block = name_of(w, n, pointee_of_variable(w, n, w[i + 1]));
        if (!block) block = name_of(w, n, w[i + 1]); /* an acceleration structure: no block */
        long want = lookup(md->bind, block);
        if (want != (long)w[i + 3] || w[i + 3] >= md->bind_count)
          fprintf(stderr, "%s: buffer %s at binding %u, the contract says %ld (of %u)\n", md->name,
                  block ? block : "?", w[i + 3], want, md->bind_count);
        CHECK_EQ_INT(w[i + 3], want);
        CHECK(w[i + 3] < md->bind_count);
        ++bindings;
      } else if (op == OP_DECORATE && w[i + 2] == DEC_SPEC_ID) {
        const char *c = name_of(w, n, w[i + 1]);
        long want = lookup(md->spec, c);
        if (want != (long)w[i + 3])
          fprintf(stderr, "%s: constant %s has SpecId %u, the contract says %ld\n", md->name, c ? c : "?",
                  w[i + 3], want);
        CHECK_EQ_INT(w[i + 3], want);
      }
      i += len;
    }
    if (bindings == 0) fprintf(stderr, "%s: no bindings found\n", md->name);
    CHECK(bindings > 0);
  }
  return pbt_done();
}
