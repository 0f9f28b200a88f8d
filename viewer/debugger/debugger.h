// The debugger's core: an intersection tester, a light-sample tester, a
// BSDF sampler and a path inspector that replays one sample of one pixel
// exactly and lists every step of its path. The viewer's server calls
// these functions (in a worker process) and sends each result's to_json()
// to the page: its json() (a value of common/json.h, see json_values.h) as
// write_json lays it out.
//
// Errors: absurd input (a zero or NaN direction, a negative radius,
// min_t > max_t, a pixel or sample index out of range, ...) throws
// InputError with a one-line message. The build's own code failing (a C++
// exception from a student's function) is not thrown: the result's `error`
// names the function, and `todos` lists the unfinished functions (the
// starter kit's TODO stubs) that were reached.
#pragma once
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/intersector.h"
#include "common/json.h"
#include "common/lights.h"
#include "pathtracer/options.h"
#include "common/scene.h"

namespace pt::debug {

// Thrown for input no function should be called with.
class InputError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

// ------------------------------------------------------------------
// Intersection tester

// A ray as typed in the page. The direction is used as given (not
// normalised), so t is measured in units of its length.
struct RayInput {
  Vec3 origin;
  Vec3 direction;
  float min_t = 0.0f;
  float max_t = kInfinity;
};

struct IntersectionResult {
  std::string function;        // "intersect_triangle" or "intersect_sphere"
  Ray ray;                     // the ray passed in
  bool hit = false;
  float t = 0;                 // on a hit
  Vec3 point;                  // ray.at(t), on a hit
  Vec3 normal;                 // the normal the function reported, on a hit
  int material = -1;           // the material it reported, on a hit
  float max_t_after = 0;       // r.max_t after the call (the contract: t on a hit, unchanged on a miss)
  std::vector<std::string> todos;  // TODO stubs reached ("Part 1: intersect_triangle (...)")
  std::string error;           // the function threw: "intersect_triangle: <what>"
  bool ok() const { return error.empty(); }
  Json json() const;
  std::string to_json() const { return write_json(json()); }
};

// Calls the build's intersect_triangle / intersect_sphere (part 1) on the ray.
IntersectionResult test_ray_triangle(const Triangle& tri, const RayInput& ray);
IntersectionResult test_ray_sphere(const Sphere& sphere, const RayInput& ray);
// A primitive picked in the scene, numbered as Hit::primitive: triangles
// first, then spheres (num_triangles + sphere index).
IntersectionResult test_ray_primitive(const Scene& scene, int primitive, const RayInput& ray);

// ------------------------------------------------------------------
// Light-sample tester

struct LightSampleTest {
  float u1 = 0, u2 = 0;        // the uniform numbers passed to sample_light
  LightSample sample;          // what sample_light returned
  float cos_theta = 0;         // dot(normal, wi)
  bool shadow_tested = false;  // a shadow ray was traced (geometry given, light along it, cos_theta > 0)
  Ray shadow_ray;              // from the point, min_t = kRayEpsilon, max_t = distance - kRayEpsilon
  bool blocked = false;
  Json json() const;
};

struct LightSamplesResult {
  int light = -1;
  std::string light_type;      // "area", "point", ...
  Vec3 point, normal;          // normal as given, normalised
  uint64_t seed = 0;
  std::vector<LightSampleTest> samples;
  std::vector<std::string> todos;
  std::string error;
  bool ok() const { return error.empty(); }
  Json json() const;
  std::string to_json() const { return write_json(json()); }
};

// The most samples one call takes.
constexpr int kMaxLightSamples = 1 << 20;

// `n` samples of scene.lights[light_index] seen from `point` (with surface
// normal `normal`, for cos theta), with the uniform numbers of Rng(seed).
// With `geometry`, each sample that can contribute also gets its shadow ray
// traced as the light-sampling estimator traces it.
LightSamplesResult sample_light_many(const Scene& scene, int light_index, const Vec3& point, const Vec3& normal,
                                     int n, uint64_t seed, const Intersector* geometry = nullptr);

// ------------------------------------------------------------------
// BSDF sampler

// One call of the material's sample_f.
struct BsdfSampleTest {
  float u1 = 0, u2 = 0;        // the uniform numbers passed
  Vec3 wi_local, wi;           // the direction drawn, local (z = normal) and in the world
  Color f{0.0f};
  float pdf = 0;               // as sample_f reported it (0: no direction)
  float pdf_model = 0;         // the model's pdf(wo, wi) for that direction
  Json json() const;
};

// A non-delta BSDF: the directions' density over theta (the angle to the
// normal) in bins, against the pdf's. A bin's `expected` count is n times
// the integral of the model's pdf over the bin (a fine midpoint grid in
// theta and phi); z = (count - expected) / sqrt(expected (1 - expected / n)).
struct BsdfHistogramBin {
  float theta_lo = 0, theta_hi = 0;  // degrees
  int count = 0;
  double expected = 0;
  double sampled_density = 0;        // count / (n * the bin's solid angle), per steradian
  double pdf_density = 0;            // expected / (n * the bin's solid angle): the pdf's mean over the bin
  double z = 0;
  bool judged = false;               // expected >= kBsdfMinExpected (the others are judged pooled)
  Json json() const;
};

// A delta BSDF: each distinct direction drawn (mirror: one; glass: the
// reflection and the refraction), how often, and the probability sample_f
// reported for that choice (glass: the Fresnel reflectance and 1 - it).
struct BsdfDirection {
  Vec3 wi_local, wi;
  std::string scatter;         // "reflected" or "refracted"
  int count = 0;
  float pdf = 0;               // the probability of this choice, as reported
  Color f{0.0f};
  Color weight{0.0f};          // f |cos theta| / pdf
  double z = 0;                // (count - n pdf) / sqrt(n pdf (1 - pdf))
  // The geometry of the choice: reflected, how far wi is from wo mirrored
  // about the normal (|wi - (-wo.x, -wo.y, wo.z)|); refracted, sin theta_o
  // / sin theta_i (Snell's law: the ratio of the indices, ior going in).
  float mirror_error = 0, sine_ratio = 0;
  Json json() const;
};

// Below this expected count a bin is too small for the normal bound: such
// bins are judged together, pooled into one (always judged).
constexpr double kBsdfMinExpected = 10;
// The bound on |z| of each judged bin (and of the pool, and of each delta
// direction): two-sided, at most 61 tests, so a correct sampler is flagged
// with probability at most 61 x 2 x Phi(-4.5) = 4.2e-4 (Bonferroni).
constexpr double kBsdfZBound = 4.5;

struct BsdfSamplesResult {
  int material = -1;
  std::string material_name;   // "name (type)"
  std::string model;           // the BSDF model the render gives it at the part (common/bsdf.h)
  bool delta = false;
  Vec3 point, normal, wo, wo_local;
  uint64_t seed = 0;
  std::vector<BsdfSampleTest> samples;
  int no_direction = 0;        // samples with pdf 0 (no bounce ray: the path ends)
  int pdf_mismatches = 0;      // non-delta: samples whose reported pdf differs from pdf(wo, wi) (relative 1e-3)
  // Non-delta: the histogram (0-90 degrees when neither the samples nor the
  // pdf go below the surface, else 0-180), the pdf's integral over the
  // sphere (1 minus the probability of no direction), the pool of small bins.
  std::vector<BsdfHistogramBin> histogram;
  double pdf_integral = 0;
  int pooled_count = 0;
  double pooled_expected = 0, pooled_z = 0;
  std::vector<BsdfDirection> directions;  // delta only
  bool agrees = false;         // every |z| within kBsdfZBound (and no sample where the pdf is 0)
  std::string verdict;         // one line: what agrees or what does not
  std::vector<std::string> todos;
  std::string error;
  bool ok() const { return error.empty(); }
  Json json() const;
  std::string to_json() const { return write_json(json()); }
};

constexpr int kMaxBsdfSamples = 1 << 16;

// `n` calls of `m`'s sample_f (the model the material has, common/bsdf.h)
// at a surface point with normal `normal`, light leaving along `wo` (world,
// pointing away from the surface), with the uniform numbers of Rng(seed);
// then the histogram (or the delta directions) and the verdict.
BsdfSamplesResult sample_bsdf_many(const Material& m, const Vec3& point, const Vec3& normal, const Vec3& wo, int n,
                                   uint64_t seed);

// The same from the first hit of the camera ray through the centre of
// pixel (x, y) ((0, 0) bottom-left), wo = the ray's reverse, with the
// materials the render gives opts.part. No hit is an InputError.
BsdfSamplesResult sample_bsdf_at_pixel(const Scene& scene, const Intersector& geometry, const RenderOptions& opts,
                                       int x, int y, int n, uint64_t seed);

// ------------------------------------------------------------------
// Environment map's sampling density

// Where the render's sampler of the -e map draws directions: each texel's
// probability (pathtracer/env_probability.h, the picture of `pathtracer
// --env-probability`), as a grey PNG on a log scale about the average
// texel's 1/(w h), and figures of it.
struct EnvironmentDensityResult {
  int part = 0;
  std::string sampler;         // "importance (part 8)" or "uniform over the sphere"
  int width = 0, height = 0;
  std::vector<uint8_t> png;    // 8-bit grey, the map's size
  double total = 0;            // the probabilities' sum (1 but for rounding; 0: empty distributions)
  double max_ratio = 0;        // the largest probability times w h (1: as likely as the average texel)
  double top_share = 0;        // the probability of the 1% most likely texels
  std::string note;            // e.g. the distributions are empty
  std::vector<std::string> todos;
  std::string error;
  bool ok() const { return error.empty(); }
  Json json() const;           // the PNG as a data: URL
  std::string to_json() const { return write_json(json()); }
};

// The density of the scene's environment light (an InputError when it has
// none: no -e), under the sampler opts.part gives it (parts 3 on).
EnvironmentDensityResult environment_density(const Scene& scene, const RenderOptions& opts);

// ------------------------------------------------------------------
// Path inspector

// One light sample taken by the direct-light estimate at a step: a call of
// sample_light the build made (common/path_recorder.h reports each), with
// the shadow ray that followed its direction, if one did.
struct LightSampleStep {
  int light = -1;              // index in scene.lights
  float u1 = 0, u2 = 0;
  LightSample sample;          // direction, distance, pdf, radiance
  float cos_theta = 0;         // dot(hit normal, wi)
  Color bsdf{0.0f};            // f(wo, wi) of the hit's material
  bool shadow_traced = false;
  Ray shadow_ray;
  bool blocked = false;
  // "lit", "blocked", or without a shadow ray: "below the surface", "zero
  // pdf", "at the surface (shorter than the ray epsilon)", or "not traced"
  // (it could have lit the point)
  std::string verdict;
  Color contribution{0.0f};    // f L cos / pdf when lit (before the estimator's averaging)
  Json json() const;
};

// One direction of the hemisphere estimate (-H) at a step.
struct HemisphereProbe {
  Ray ray;
  bool hit = false;
  Hit probe_hit;
  Color radiance{0.0f};        // emission of what it hit, or the sky it escaped to
  float cos_theta = 0;
  Json json() const;
};

// One hit of the path and what the estimator did there.
struct PathStep {
  int bounce = 0;              // 1: where the camera ray hits; 2: the first bounce ray's hit; ...
  int depth = 0;               // bounces left by the contract (-m at the camera ray's hit), parts 4-5
  Ray ray;                     // the ray that found this hit, as traced
  Hit hit;
  Vec3 point;
  std::string material;        // the material's name and type, e.g. "red (diffuse)"
  // The BSDF model the render gives the material at its part (common/bsdf.h):
  // "diffuse", "mirror", "glass", "microfacet", ..., or "not rendered" (a
  // later part's material: black).
  std::string bsdf_model;
  // A delta BSDF (mirror, glass, refraction; part 6): no light samples, the
  // light is what the bounce ray reaches (`reached`).
  bool delta = false;
  Color emission{0.0f};

  bool direct_estimated = false;
  std::string estimator;       // "light sampling" or "hemisphere sampling"
  Color direct{0.0f};          // what one_bounce_radiance returned
  bool direct_counted = false; // added to the path by the contract (-o, --indirect-only)
  std::vector<LightSampleStep> light_samples;
  std::vector<HemisphereProbe> hemisphere_samples;
  std::vector<Ray> other_shadow_rays;  // occlusion queries not following a light sample

  Color path_weight{1.0f};     // product of f cos / pdf (and 1 / survival) of the bounces before
  Color radiance_added{0.0f};  // path_weight * direct when counted

  std::vector<float> roulette_draws;  // numbers drawn after the direct estimate and before the BSDF sample
  bool roulette_applies = false;      // the contract plays Russian roulette here
  float continue_probability = 1.0f;

  bool bsdf_sampled = false;
  float bsdf_u1 = 0, bsdf_u2 = 0;
  Vec3 bsdf_wo_local, bsdf_wi_local, bsdf_wi;
  Color bsdf_f{0.0f};
  float bsdf_pdf = 0, bsdf_cos_theta = 0;
  std::string bsdf_scatter;    // "reflected" (wi on wo's side of the surface) or "refracted"

  // A delta step's light: the emission of the hit (or the sky) its bounce
  // ray reaches, added as path weight x f |cos| / pdf x reached when the
  // contract counts it (-o, --indirect-only, as a direct estimate).
  Color reached{0.0f};
  bool reached_counted = false;

  bool next_traced = false;    // a bounce ray left this hit
  Ray next_ray;
  bool next_hit = false;
  Json json() const;
};

struct PathRecord {
  int part = 0;
  int x = 0, y = 0, sample = 0;
  uint64_t seed = 0;
  int samples_per_pixel = 0;
  int samples_taken = 0;       // by the pixel function (part 5: adaptive)

  Ray camera_ray;
  bool camera_hit = false;
  Color zero_bounce{0.0f};     // the emission (or sky) the camera ray sees, as added
  std::vector<PathStep> steps;
  std::string end;             // why the path ended

  Color returned{0.0f};        // what the radiance function returned: the sample's value in the render loop
  Color sum_of_contributions{0.0f};  // zero_bounce + (radiance_added of the steps, summed in order)
  bool exact = false;          // sum_of_contributions == returned, bit for bit
  // Within float rounding (relative 1e-5 per channel): what an estimator
  // that follows the contracts but groups its sums differently (a
  // recursive part 4, say) gets. False means it computed something else.
  bool agrees = false;
  std::vector<std::string> notes;
  std::vector<std::string> todos;
  std::string error;
  bool ok() const { return error.empty(); }
  Json json() const;
  std::string to_json() const { return write_json(json()); }
};

// The closest-hit structure the command line uses for opts.part: every
// primitive tested (part 1) or the BVH (parts 2-5).
std::unique_ptr<Intersector> make_geometry(const Scene& scene, const RenderOptions& opts);

// Replays sample `sample_index` of pixel (x, y) ((0, 0) bottom-left) as the
// render of `opts` computes it (the part's pixel function, radiance
// function and random numbers) and records its path. `scene.camera` must be
// configured for opts (configure_camera). Part 5 replays the pixel's
// adaptive sampling up to the sample; a sample it did not take is an
// InputError. Safe to call from several threads at once (the recorder is
// per call and per thread; `geometry` is only queried).
PathRecord record_path(const Scene& scene, const Intersector& geometry, const RenderOptions& opts, int x, int y,
                       int sample_index);

}  // namespace pt::debug
