/* BSDFs in the local shading frame (normal = +z), one section a material
 * type: Lambertian diffuse, diffuse transmission, dielectric and thin
 * dielectric, conductor (smooth, or rough with the GGX / Trowbridge-Reitz
 * microfacet distribution and visible-normal sampling), and pbrt-v4's
 * layered BSDFs (coated diffuse, coated conductor). Shared by host (tests)
 * and kernels.
 *
 * Values follow pbrt-v4's definitions (radiance transport: transmission is
 * divided by the squared relative index). Reflection-only materials are
 * two-sided: directions below the surface are mirrored above it. */
#ifndef KERNELS_BSDF_H
#define KERNELS_BSDF_H

#include "feature_mask.h"
#include "mis.h"
#include "rng.h"
#include "scene_types.h"
#include "../common/vec3.h"

typedef struct {
    Vec3 wi;
    Vec3 f;    /* BSDF value (not multiplied by the cosine) */
    float pdf; /* solid-angle density; for delta lobes the discrete probability */
    int is_delta;
    int is_transmission;
    float etap; /* relative index crossed by a transmission, else 1 */
} BsdfSample;

KERNEL_FN float clamp01(float x)
{
    return x < 0.0f ? 0.0f : (x > 1.0f ? 1.0f : x);
}

KERNEL_FN Vec3 reflect_about(Vec3 wo, Vec3 n)
{
    return v_sub(v_scale(n, 2.0f * v_dot(wo, n)), wo);
}

/* Refracts wo through a surface with normal n (either side) and relative
 * index eta (inside over outside). Returns 0 on total internal reflection. */
KERNEL_FN int refract_about(Vec3 wo, Vec3 n, float eta, float *etap, Vec3 *wt)
{
    float cos_i = v_dot(n, wo);
    if (cos_i < 0.0f) {
        eta = 1.0f / eta;
        cos_i = -cos_i;
        n = v_scale(n, -1.0f);
    }
    float sin2_i = 1.0f - cos_i * cos_i;
    sin2_i = sin2_i > 0.0f ? sin2_i : 0.0f;
    float sin2_t = sin2_i / (eta * eta);
    if (sin2_t >= 1.0f)
        return 0;
    float cos_t = sqrt_float(1.0f - sin2_t);
    *wt = v_add(v_scale(wo, -1.0f / eta), v_scale(n, cos_i / eta - cos_t));
    *etap = eta;
    return 1;
}

/* Unpolarized Fresnel reflectance of a dielectric interface. */
KERNEL_FN float fresnel_dielectric(float cos_i, float eta)
{
    cos_i = cos_i < -1.0f ? -1.0f : (cos_i > 1.0f ? 1.0f : cos_i);
    if (cos_i < 0.0f) {
        eta = 1.0f / eta;
        cos_i = -cos_i;
    }
    float sin2_t = (1.0f - cos_i * cos_i) / (eta * eta);
    if (sin2_t >= 1.0f)
        return 1.0f;
    float cos_t = sqrt_float(1.0f - sin2_t);
    float parallel = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    float perpendicular = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    return 0.5f * (parallel * parallel + perpendicular * perpendicular);
}

/* Fresnel reflectance of a conductor with complex index eta + i k, for
 * 0 <= cos_i <= 1. Complex arithmetic spelled out. */
KERNEL_FN float fresnel_conductor(float cos_i, float eta, float k)
{
    cos_i = clamp01(cos_i);
    float sin2_i = 1.0f - cos_i * cos_i;
    /* sin2_t = sin2_i / (eta + ik)^2 */
    float e2_re = eta * eta - k * k, e2_im = 2.0f * eta * k;
    float e2_norm = e2_re * e2_re + e2_im * e2_im;
    float s_re = sin2_i * e2_re / e2_norm, s_im = -sin2_i * e2_im / e2_norm;
    /* cos_t = sqrt(1 - sin2_t) */
    float z_re = 1.0f - s_re, z_im = -s_im;
    float z_abs = sqrt_float(z_re * z_re + z_im * z_im);
    float c_re = 0.0f, c_im = 0.0f;
    if (z_abs > 0.0f) {
        float t1 = sqrt_float(0.5f * (z_abs + (z_re < 0.0f ? -z_re : z_re)));
        float t2 = 0.5f * z_im / t1;
        if (z_re >= 0.0f) {
            c_re = t1;
            c_im = t2;
        } else {
            c_re = t2 < 0.0f ? -t2 : t2;
            c_im = z_im < 0.0f ? -t1 : t1;
        }
    }
    /* r_parallel = (eta cos_i - cos_t) / (eta cos_i + cos_t), eta complex */
    float a_re = eta * cos_i - c_re, a_im = k * cos_i - c_im;
    float b_re = eta * cos_i + c_re, b_im = k * cos_i + c_im;
    float parallel = (a_re * a_re + a_im * a_im) / (b_re * b_re + b_im * b_im);
    /* r_perpendicular = (cos_i - eta cos_t) / (cos_i + eta cos_t) */
    float ec_re = eta * c_re - k * c_im, ec_im = eta * c_im + k * c_re;
    float p_re = cos_i - ec_re, p_im = -ec_im;
    float q_re = cos_i + ec_re, q_im = ec_im;
    float perpendicular = (p_re * p_re + p_im * p_im) / (q_re * q_re + q_im * q_im);
    return 0.5f * (parallel + perpendicular);
}

/* ---- GGX (Trowbridge-Reitz) ---- */

KERNEL_FN float ggx_d(Vec3 wm, float ax, float ay)
{
    float cos2 = wm.z * wm.z;
    if (cos2 <= 0.0f)
        return 0.0f;
    float e = (wm.x * wm.x / (ax * ax) + wm.y * wm.y / (ay * ay)) / cos2;
    float denominator = PI_F * ax * ay * cos2 * cos2 * (1.0f + e) * (1.0f + e);
    return 1.0f / denominator;
}

KERNEL_FN float ggx_lambda(Vec3 w, float ax, float ay)
{
    float cos2 = w.z * w.z;
    if (cos2 <= 0.0f)
        return 0.0f;
    float alpha2_tan2 = (w.x * w.x * ax * ax + w.y * w.y * ay * ay) / cos2;
    return 0.5f * (sqrt_float(1.0f + alpha2_tan2) - 1.0f);
}

KERNEL_FN float ggx_g1(Vec3 w, float ax, float ay)
{
    return 1.0f / (1.0f + ggx_lambda(w, ax, ay));
}

KERNEL_FN float ggx_g(Vec3 wo, Vec3 wi, float ax, float ay)
{
    return 1.0f / (1.0f + ggx_lambda(wo, ax, ay) + ggx_lambda(wi, ax, ay));
}

/* Density of visible normals wm seen from w. */
KERNEL_FN float ggx_visible_d(Vec3 w, Vec3 wm, float ax, float ay)
{
    float cos_w = w.z < 0.0f ? -w.z : w.z;
    if (cos_w == 0.0f)
        return 0.0f;
    float wdotm = v_dot(w, wm);
    return ggx_g1(w, ax, ay) / cos_w * ggx_d(wm, ax, ay) * (wdotm < 0.0f ? -wdotm : wdotm);
}

/* Samples a visible normal (Heitz 2018), in the +z hemisphere. */
KERNEL_FN Vec3 ggx_sample_visible(Vec3 w, float ax, float ay, float u1, float u2)
{
    Vec3 wh = v_normalize(vec3(ax * w.x, ay * w.y, w.z));
    if (wh.z < 0.0f)
        wh = v_scale(wh, -1.0f);
    Vec3 t1 = wh.z < 0.99999f ? v_normalize(v_cross(vec3(0.0f, 0.0f, 1.0f), wh)) : vec3(1.0f, 0.0f, 0.0f);
    Vec3 t2 = v_cross(wh, t1);
    float r = sqrt_float(u1), phi = 2.0f * PI_F * u2;
    float px = r * cos_float(phi), py = r * sin_float(phi);
    float h = sqrt_float(1.0f - px * px);
    float s = 0.5f * (1.0f + wh.z);
    py = (1.0f - s) * h + s * py;
    float pz2 = 1.0f - px * px - py * py;
    float pz = sqrt_float(pz2 > 0.0f ? pz2 : 0.0f);
    Vec3 nh = v_add(v_add(v_scale(t1, px), v_scale(t2, py)), v_scale(wh, pz));
    return v_normalize(vec3(ax * nh.x, ay * nh.y, nh.z > 1e-6f ? nh.z : 1e-6f));
}

/* Without rough materials in the build, every surface is smooth and the
 * GGX code drops out. */
KERNEL_FN int alpha_is_smooth(float alpha_x, float alpha_y)
{
    return !GMON_HAS_ROUGH || (alpha_x < SMOOTH_ALPHA && alpha_y < SMOOTH_ALPHA);
}

KERNEL_FN int material_is_smooth(const Material *m)
{
    return alpha_is_smooth(m->alpha_x, m->alpha_y);
}

KERNEL_FN Vec3 cosine_hemisphere(float u1, float u2)
{
    float r = sqrt_float(u1), phi = 2.0f * PI_F * u2;
    float z2 = 1.0f - u1;
    return vec3(r * cos_float(phi), r * sin_float(phi), sqrt_float(z2 > 0.0f ? z2 : 0.0f));
}

KERNEL_FN void bsdf_sample_clear(BsdfSample *s)
{
    s->is_delta = 0;
    s->is_transmission = 0;
    s->etap = 1.0f;
    s->pdf = 0.0f;
    s->f = vec3(0.0f, 0.0f, 0.0f);
}

/* Microfacet reflection, both directions in +z: D G / (4 cos_o cos_i), the
 * half vector and the density of sampling wi by visible normals. */
KERNEL_FN float microfacet_reflection(Vec3 wo, Vec3 wi, float ax, float ay, Vec3 *wm_out, float *pdf)
{
    Vec3 wm = v_add(wo, wi);
    float len2 = v_dot(wm, wm);
    *pdf = 0.0f;
    if (wo.z <= 0.0f || wi.z <= 0.0f || len2 == 0.0f)
        return 0.0f;
    wm = v_scale(wm, 1.0f / sqrt_float(len2));
    *wm_out = wm;
    *pdf = ggx_visible_d(wo, wm, ax, ay) / (4.0f * v_dot(wo, wm));
    return ggx_d(wm, ax, ay) * ggx_g(wo, wi, ax, ay) / (4.0f * wo.z * wi.z);
}

/* ---- dielectric interface: the dielectric material and the coating of the
 * layered ones ----
 *
 * Relative index eta (the -z side over the +z side), roughness (ax, ay).
 * `radiance`: radiance transport (transmission divided by etap^2), else
 * importance (the layered BSDFs trace the light's side with it). `lobes`
 * restricts sampling and its density to reflection or transmission, as
 * pbrt-v4's BxDFReflTransFlags; f is the full BSDF either way. */
#define LOBE_REFLECTION 1
#define LOBE_TRANSMISSION 2
#define LOBE_ALL 3

/* The chance of picking reflection (r) or transmission (1 - r) among `lobes`. */
KERNEL_FN float lobe_chance(float r, int lobe, int lobes)
{
    if (lobes == LOBE_ALL)
        return lobe == LOBE_REFLECTION ? r : 1.0f - r;
    return (lobes & lobe) ? 1.0f : 0.0f;
}

KERNEL_FN float dielectric_f(float eta, float ax, float ay, Vec3 wo, Vec3 wi, int radiance, int lobes, float *pdf)
{
    *pdf = 0.0f;
    if (alpha_is_smooth(ax, ay) || wo.z == 0.0f || wi.z == 0.0f)
        return 0.0f;
    int reflect = wo.z * wi.z > 0.0f;
    float etap = reflect ? 1.0f : (wo.z > 0.0f ? eta : 1.0f / eta);
    Vec3 wm = v_add(v_scale(wi, etap), wo);
    if (v_dot(wm, wm) == 0.0f)
        return 0.0f;
    wm = v_normalize(wm);
    if (wm.z < 0.0f)
        wm = v_scale(wm, -1.0f);
    float wi_m = v_dot(wi, wm), wo_m = v_dot(wo, wm);
    if (wi_m * wi.z < 0.0f || wo_m * wo.z < 0.0f)
        return 0.0f; /* back-facing microfacet */
    float r = fresnel_dielectric(wo_m, eta), t = 1.0f - r;
    float d = ggx_d(wm, ax, ay), g = ggx_g(wo, wi, ax, ay);
    if (reflect) {
        *pdf = ggx_visible_d(wo, wm, ax, ay) / (4.0f * (wo_m < 0.0f ? -wo_m : wo_m)) *
               lobe_chance(r, LOBE_REFLECTION, lobes);
        float value = d * g * r / (4.0f * wi.z * wo.z);
        return value < 0.0f ? -value : value;
    }
    float denominator = wi_m + wo_m / etap;
    denominator *= denominator;
    *pdf = ggx_visible_d(wo, wm, ax, ay) * (wi_m < 0.0f ? -wi_m : wi_m) / denominator *
           lobe_chance(r, LOBE_TRANSMISSION, lobes);
    float value = t * d * g * (wi_m * wo_m / (wi.z * wo.z * denominator));
    value = value < 0.0f ? -value : value;
    return radiance ? value / (etap * etap) : value;
}

KERNEL_FN int dielectric_sample(float eta, float ax, float ay, Vec3 wo, float u_lobe, float u1, float u2, int radiance,
                                int lobes, BsdfSample *s)
{
    bsdf_sample_clear(s);
    if (wo.z == 0.0f)
        return 0;
    if (alpha_is_smooth(ax, ay)) {
        float r = fresnel_dielectric(wo.z, eta), t = 1.0f - r;
        float pick_reflection = lobe_chance(r, LOBE_REFLECTION, lobes);
        if (lobes != LOBE_ALL && r == (lobes == LOBE_REFLECTION ? 0.0f : 1.0f))
            return 0; /* the only lobe allowed carries nothing */
        s->is_delta = 1;
        if (u_lobe < pick_reflection) {
            s->wi = vec3(-wo.x, -wo.y, wo.z);
            s->pdf = pick_reflection;
            float value = r / (wo.z < 0.0f ? -wo.z : wo.z);
            s->f = vec3(value, value, value);
            return 1;
        }
        if (!refract_about(wo, vec3(0.0f, 0.0f, 1.0f), eta, &s->etap, &s->wi))
            return 0;
        s->is_transmission = 1;
        s->pdf = lobe_chance(r, LOBE_TRANSMISSION, lobes);
        float value = t / (s->wi.z < 0.0f ? -s->wi.z : s->wi.z);
        if (radiance)
            value /= s->etap * s->etap;
        s->f = vec3(value, value, value);
        return 1;
    }
    Vec3 wm = ggx_sample_visible(wo, ax, ay, u1, u2);
    float r = fresnel_dielectric(v_dot(wo, wm), eta);
    if (u_lobe < lobe_chance(r, LOBE_REFLECTION, lobes)) {
        s->wi = reflect_about(wo, wm);
        if (s->wi.z * wo.z <= 0.0f)
            return 0;
    } else {
        float etap = 1.0f;
        if (!refract_about(wo, wm, eta, &etap, &s->wi) || s->wi.z * wo.z >= 0.0f || s->wi.z == 0.0f)
            return 0;
        s->is_transmission = 1;
        s->etap = etap;
    }
    float value = dielectric_f(eta, ax, ay, wo, s->wi, radiance, lobes, &s->pdf);
    s->f = vec3(value, value, value);
    return s->pdf > 0.0f;
}

/* ---- thin dielectric: a slab whose internal reflections are summed
 * (pbrt-v4's ThinDielectricBxDF); only delta lobes, transmission straight
 * through ---- */

KERNEL_FN int thin_dielectric_sample(float eta, Vec3 wo, float u_lobe, BsdfSample *s)
{
    bsdf_sample_clear(s);
    float cos_o = wo.z < 0.0f ? -wo.z : wo.z;
    if (cos_o == 0.0f)
        return 0;
    float r = fresnel_dielectric(cos_o, eta), t = 1.0f - r;
    if (r < 1.0f) {
        r += t * t * r / (1.0f - r * r);
        t = 1.0f - r;
    }
    s->is_delta = 1;
    if (u_lobe < r) {
        s->wi = vec3(-wo.x, -wo.y, wo.z);
        s->pdf = r;
        s->f = vec3(r / cos_o, r / cos_o, r / cos_o);
    } else {
        s->wi = v_scale(wo, -1.0f);
        s->is_transmission = 1;
        s->pdf = t;
        s->f = vec3(t / cos_o, t / cos_o, t / cos_o);
    }
    return s->pdf > 0.0f;
}

/* ---- conductor (wo, wi in +z; callers mirror them there) ---- */

/* pbrt-v4: a conductor given by its reflectance r instead of eta and k is
 * one with eta = 1 and k = 2 sqrt(r) / sqrt(1 - r), whose normal-incidence
 * reflectance is r (r clamped to [0, 0.9999] to keep k finite). Sets
 * channels of m's conductor_eta and conductor_k from reflectance. */
KERNEL_FN void conductor_from_reflectance(Material *m, const float reflectance[3])
{
    for (int i = 0; i < 3; ++i) {
        float r = reflectance[i] < 0.0f ? 0.0f : (reflectance[i] > 0.9999f ? 0.9999f : reflectance[i]);
        m->conductor_eta[i] = 1.0f;
        m->conductor_k[i] = 2.0f * sqrt_float(r) / sqrt_float(1.0f - r);
    }
}

KERNEL_FN Vec3 conductor_fresnel(const Material *m, float cos_i)
{
    return vec3(fresnel_conductor(cos_i, m->conductor_eta[0], m->conductor_k[0]),
                fresnel_conductor(cos_i, m->conductor_eta[1], m->conductor_k[1]),
                fresnel_conductor(cos_i, m->conductor_eta[2], m->conductor_k[2]));
}

KERNEL_FN Vec3 conductor_f(const Material *m, float ax, float ay, Vec3 wo, Vec3 wi, float *pdf)
{
    *pdf = 0.0f;
    if (alpha_is_smooth(ax, ay))
        return vec3(0.0f, 0.0f, 0.0f);
    Vec3 wm = vec3(0.0f, 0.0f, 1.0f);
    float value = microfacet_reflection(wo, wi, ax, ay, &wm, pdf);
    return v_scale(conductor_fresnel(m, v_dot(wo, wm)), value);
}

KERNEL_FN int conductor_sample(const Material *m, float ax, float ay, Vec3 wo, float u1, float u2, BsdfSample *s)
{
    if (alpha_is_smooth(ax, ay)) {
        s->is_delta = 1;
        s->wi = vec3(-wo.x, -wo.y, wo.z);
        s->pdf = 1.0f;
        s->f = v_scale(conductor_fresnel(m, wo.z), 1.0f / wo.z);
        return 1;
    }
    Vec3 wm = ggx_sample_visible(wo, ax, ay, u1, u2);
    s->wi = reflect_about(wo, wm);
    if (s->wi.z <= 0.0f)
        return 0;
    s->f = conductor_f(m, ax, ay, wo, s->wi, &s->pdf);
    return s->pdf > 0.0f;
}

/* ---- diffuse transmission: Lambertian reflection (reflectance) and
 * Lambertian transmission to the other side (transmittance), each lobe
 * sampled by its largest component ---- */

KERNEL_FN float diffuse_transmission_pick(const Material *m)
{
    float r = v_max_component(vec3_from(m->reflectance));
    float t = v_max_component(vec3_from(m->transmittance));
    return r + t > 0.0f ? r / (r + t) : 0.0f;
}

KERNEL_FN Vec3 diffuse_transmission_f(const Material *m, Vec3 wo, Vec3 wi, float *pdf)
{
    float pick = diffuse_transmission_pick(m);
    float cos_i = wi.z < 0.0f ? -wi.z : wi.z;
    if (wo.z * wi.z > 0.0f) {
        *pdf = pick * cos_i / PI_F;
        return v_scale(vec3_from(m->reflectance), 1.0f / PI_F);
    }
    *pdf = wo.z * wi.z < 0.0f ? (1.0f - pick) * cos_i / PI_F : 0.0f;
    return *pdf > 0.0f ? v_scale(vec3_from(m->transmittance), 1.0f / PI_F) : vec3(0.0f, 0.0f, 0.0f);
}

KERNEL_FN int diffuse_transmission_sample(const Material *m, Vec3 wo, float u_lobe, float u1, float u2, BsdfSample *s)
{
    Vec3 wi = cosine_hemisphere(u1, u2);
    if (wi.z <= 0.0f ||
        v_max_component(vec3_from(m->reflectance)) + v_max_component(vec3_from(m->transmittance)) <= 0.0f)
        return 0;
    int transmit = u_lobe >= diffuse_transmission_pick(m);
    float side = (wo.z < 0.0f) != transmit ? -1.0f : 1.0f;
    s->wi = vec3(wi.x, wi.y, wi.z * side);
    s->is_transmission = transmit;
    s->f = diffuse_transmission_f(m, wo, s->wi, &s->pdf);
    return s->pdf > 0.0f;
}

/* ---- the layered BSDFs (pbrt-v4's LayeredBxDF, two-sided): a dielectric
 * coating on top (z = thickness) over an opaque base (z = 0): Lambertian
 * for coated diffuse, a conductor for coated conductor. f, the sampling
 * and the density are estimated by random walks between the layers,
 * seeded by a hash of the directions (as pbrt-v4) so that the same
 * arguments give the same value. Light cannot pass the opaque base, so
 * only reflection has a value. ---- */

typedef struct {
    uint64_t key;
    uint32_t next;
} WalkRng;

KERNEL_FN WalkRng walk_rng(Vec3 a, Vec3 b)
{
    WalkRng r;
    r.key = rng_mix(((uint64_t)float_bits(a.x) << 32) ^ float_bits(a.y) ^ 0x5851F42D4C957F2Dul);
    r.key = rng_mix(r.key ^ (((uint64_t)float_bits(a.z) << 32) | float_bits(b.x)));
    r.key = rng_mix(r.key ^ (((uint64_t)float_bits(b.y) << 32) | float_bits(b.z)));
    r.next = 0;
    return r;
}

KERNEL_FN float walk_uniform(WalkRng *r)
{
    return rng_uniform(r->key, r->next++);
}

/* Henyey-Greenstein phase function of asymmetry g, for wo and wi both
 * pointing away from the scattering point (so g > 0 scatters forward,
 * toward -wo). */
KERNEL_FN float hg_phase(Vec3 wo, Vec3 wi, float g)
{
    float d = 1.0f + g * g + 2.0f * g * v_dot(wo, wi);
    return d > 0.0f ? (1.0f - g * g) / (4.0f * PI_F * d * sqrt_float(d)) : 0.0f;
}

KERNEL_FN Vec3 hg_sample(Vec3 wo, float g, float u1, float u2)
{
    float cos_forward; /* to the forward direction -wo */
    if (g > -1e-3f && g < 1e-3f) {
        cos_forward = 1.0f - 2.0f * u1;
    } else {
        float q = (1.0f - g * g) / (1.0f + g - 2.0f * g * u1);
        cos_forward = (1.0f + g * g - q * q) / (2.0f * g);
    }
    cos_forward = cos_forward < -1.0f ? -1.0f : (cos_forward > 1.0f ? 1.0f : cos_forward);
    float sin2 = 1.0f - cos_forward * cos_forward;
    float sin_forward = sqrt_float(sin2 > 0.0f ? sin2 : 0.0f), phi = 2.0f * PI_F * u2;
    Vec3 forward = v_scale(wo, -1.0f), s, t;
    v_basis(forward, &s, &t);
    return v_add(v_add(v_scale(s, sin_forward * cos_float(phi)), v_scale(t, sin_forward * sin_float(phi))),
                 v_scale(forward, cos_forward));
}

/* Transmittance of the medium (unit extinction) over a height dz along w. */
KERNEL_FN float layer_transmittance(float dz, Vec3 w)
{
    float x = dz / w.z;
    x = x < 0.0f ? -x : x;
    return dz == 0.0f ? 1.0f : exp_float(-x);
}

KERNEL_FN int layered_has_medium(const Material *m)
{
    return m->albedo[0] > 0.0f || m->albedo[1] > 0.0f || m->albedo[2] > 0.0f;
}

/* Whether the base is a conductor (else Lambertian); with one coated type
 * in the build the test folds away. */
KERNEL_FN int layered_base_is_conductor(const Material *m)
{
    return !GMON_HAS_COATED_CONDUCTOR ? 0 : !GMON_HAS_COATED_DIFFUSE ? 1 : m->type == MAT_COATED_CONDUCTOR;
}

KERNEL_FN int layered_base_is_smooth(const Material *m)
{
    return layered_base_is_conductor(m) && alpha_is_smooth(m->base_alpha_x, m->base_alpha_y);
}

/* Every lobe a delta: a smooth coating over a smooth conductor, no medium. */
KERNEL_FN int layered_is_delta(const Material *m)
{
    return material_is_smooth(m) && layered_base_is_smooth(m) && !layered_has_medium(m);
}

/* The base, seen from inside the layer (wo.z > 0 there). */
KERNEL_FN Vec3 layered_base_f(const Material *m, Vec3 wo, Vec3 wi, float *pdf)
{
    *pdf = 0.0f;
    if (wo.z <= 0.0f || wi.z <= 0.0f)
        return vec3(0.0f, 0.0f, 0.0f);
    if (layered_base_is_conductor(m))
        return conductor_f(m, m->base_alpha_x, m->base_alpha_y, wo, wi, pdf);
    *pdf = wi.z / PI_F;
    return v_scale(vec3_from(m->reflectance), 1.0f / PI_F);
}

KERNEL_FN int layered_base_sample(const Material *m, Vec3 wo, float u1, float u2, BsdfSample *s)
{
    bsdf_sample_clear(s);
    if (wo.z <= 0.0f)
        return 0;
    if (layered_base_is_conductor(m))
        return conductor_sample(m, m->base_alpha_x, m->base_alpha_y, wo, u1, u2, s);
    s->wi = cosine_hemisphere(u1, u2);
    s->f = layered_base_f(m, wo, s->wi, &s->pdf);
    return s->pdf > 0.0f;
}

KERNEL_FN int coating_sample(const Material *m, Vec3 wo, WalkRng *rng, int radiance, int lobes, BsdfSample *s)
{
    float u_lobe = walk_uniform(rng), u1 = walk_uniform(rng), u2 = walk_uniform(rng);
    return dielectric_sample(m->eta, m->alpha_x, m->alpha_y, wo, u_lobe, u1, u2, radiance, lobes, s) && s->pdf > 0.0f &&
           s->wi.z != 0.0f && v_max_component(s->f) > 0.0f;
}

KERNEL_FN float coating_f(const Material *m, Vec3 wo, Vec3 wi, int lobes, float *pdf)
{
    return dielectric_f(m->eta, m->alpha_x, m->alpha_y, wo, wi, 1, lobes, pdf);
}

/* The density of the light's way in along wi reaching the layer as `down`:
 * the strategy that competes with a walk's sampled exit toward wi. Both
 * are densities of the direction inside the layer, so their MIS weights
 * sum to 1. (pbrt-v4 weighs by the density of wi given the inside
 * direction instead, a density over other directions: its estimate then
 * differs from its own sampling, by 8% of the walks' part for a rough
 * coating of alpha 0.3.) */
KERNEL_FN float coating_in_pdf(const Material *m, Vec3 wi, Vec3 down)
{
    float pdf = 0.0f;
    coating_f(m, wi, down, LOBE_TRANSMISSION, &pdf);
    return pdf;
}

KERNEL_FN Vec3 layered_f(const Material *m, Vec3 wo, Vec3 wi)
{
    Vec3 zero = vec3(0.0f, 0.0f, 0.0f);
    if (wo.z < 0.0f) {
        wo = v_scale(wo, -1.0f);
        wi = v_scale(wi, -1.0f);
    }
    if (wi.z <= 0.0f || wo.z == 0.0f)
        return zero;
    float thickness = m->thickness, pdf = 0.0f;
    int coating_smooth = material_is_smooth(m), base_smooth = layered_base_is_smooth(m);
    int medium = layered_has_medium(m);
    Vec3 albedo = vec3_from(m->albedo);
    float samples = (float)m->sample_count;
    float reflected = coating_f(m, wo, wi, LOBE_ALL, &pdf) * samples;
    Vec3 f = vec3(reflected, reflected, reflected);
    WalkRng rng = walk_rng(wo, wi);
    for (uint32_t sample = 0; sample < m->sample_count; ++sample) {
        BsdfSample wos, wis;
        /* Into the layer along wo, and a virtual light's way in along wi. */
        if (!coating_sample(m, wo, &rng, 1, LOBE_TRANSMISSION, &wos) ||
            !coating_sample(m, wi, &rng, 0, LOBE_TRANSMISSION, &wis))
            continue;
        Vec3 beta = v_scale(wos.f, (wos.wi.z < 0.0f ? -wos.wi.z : wos.wi.z) / wos.pdf);
        Vec3 light_in = v_scale(wis.f, 1.0f / wis.pdf); /* the light's path weight through the coating */
        Vec3 w = wos.wi, to_light = v_scale(wis.wi, -1.0f);
        float z = thickness;
        for (uint32_t depth = 0; depth < m->max_depth; ++depth) {
            float largest = v_max_component(beta);
            if (depth > 3 && largest < 0.25f) {
                float q = 1.0f - largest;
                if (walk_uniform(&rng) < q)
                    break;
                beta = v_scale(beta, 1.0f / (1.0f - q));
            }
            if (!medium) {
                z = z == thickness ? 0.0f : thickness;
                beta = v_scale(beta, layer_transmittance(thickness, w));
            } else {
                float u = walk_uniform(&rng);
                float dz = -log_float(1.0f - u) * (w.z < 0.0f ? -w.z : w.z);
                float zp = w.z > 0.0f ? z + dz : z - dz;
                if (zp == z)
                    continue;
                if (zp > 0.0f && zp < thickness) {
                    /* Scattering in the medium: toward the light through the
                     * coating along wis, then on along the phase function. */
                    Vec3 back = v_scale(w, -1.0f);
                    float phase = hg_phase(back, to_light, m->g);
                    float weight = coating_smooth ? 1.0f : power_heuristic(wis.pdf, phase);
                    f = v_add(f, v_scale(v_mul(v_mul(beta, albedo), light_in),
                                         phase * weight * layer_transmittance(zp - thickness, wis.wi)));
                    Vec3 next = hg_sample(back, m->g, walk_uniform(&rng), walk_uniform(&rng));
                    float next_pdf = hg_phase(back, next, m->g);
                    if (!(next_pdf > 0.0f) || next.z == 0.0f)
                        continue;
                    beta = v_mul(beta, albedo); /* phase / pdf = 1 */
                    w = next;
                    z = zp;
                    if (w.z > 0.0f && !coating_smooth) {
                        float unused = 0.0f;
                        Vec3 down = v_scale(w, -1.0f);
                        float exit_f = coating_f(m, down, wi, LOBE_TRANSMISSION, &unused);
                        if (exit_f > 0.0f)
                            f = v_add(f, v_scale(beta, layer_transmittance(zp - thickness, w) * exit_f *
                                                           power_heuristic(next_pdf, coating_in_pdf(m, wi, down))));
                    }
                    continue;
                }
                z = zp < 0.0f ? 0.0f : thickness;
            }
            BsdfSample bs;
            if (z == thickness) {
                /* Back down off the coating's underside. */
                if (!coating_sample(m, v_scale(w, -1.0f), &rng, 1, LOBE_REFLECTION, &bs))
                    break;
            } else {
                Vec3 up = v_scale(w, -1.0f);
                if (!base_smooth) {
                    /* The light through the coating, off the base. */
                    float base_pdf = 0.0f;
                    Vec3 base = layered_base_f(m, up, to_light, &base_pdf);
                    float weight = coating_smooth ? 1.0f : power_heuristic(wis.pdf, base_pdf);
                    f = v_add(f, v_scale(v_mul(v_mul(beta, base), light_in),
                                         to_light.z * weight * layer_transmittance(thickness, wis.wi)));
                }
                float u1 = walk_uniform(&rng), u2 = walk_uniform(&rng);
                if (!layered_base_sample(m, up, u1, u2, &bs) || bs.wi.z == 0.0f || v_max_component(bs.f) <= 0.0f)
                    break;
                if (!coating_smooth) {
                    /* Out through the coating toward wi from the base's sample. */
                    float unused = 0.0f;
                    Vec3 down = v_scale(bs.wi, -1.0f);
                    float exit_f = coating_f(m, down, wi, LOBE_TRANSMISSION, &unused);
                    if (exit_f > 0.0f) {
                        float weight = base_smooth ? 1.0f : power_heuristic(bs.pdf, coating_in_pdf(m, wi, down));
                        Vec3 after = v_mul(beta, v_scale(bs.f, bs.wi.z / bs.pdf));
                        f = v_add(f, v_scale(after, layer_transmittance(thickness, bs.wi) * exit_f * weight));
                    }
                }
            }
            beta = v_mul(beta, v_scale(bs.f, (bs.wi.z < 0.0f ? -bs.wi.z : bs.wi.z) / bs.pdf));
            w = bs.wi;
        }
    }
    return v_scale(f, 1.0f / samples);
}

/* The density of layered_sample's directions, estimated (pbrt-v4's
 * stochastic estimate, mixed with a uniform density so that it is never 0). */
KERNEL_FN float layered_pdf(const Material *m, Vec3 wo, Vec3 wi)
{
    if (wo.z < 0.0f) {
        wo = v_scale(wo, -1.0f);
        wi = v_scale(wi, -1.0f);
    }
    float sum = 0.0f, pdf = 0.0f;
    int coating_smooth = material_is_smooth(m), base_smooth = layered_base_is_smooth(m);
    if (wi.z > 0.0f) {
        coating_f(m, wo, wi, LOBE_REFLECTION, &pdf);
        sum = (float)m->sample_count * pdf;
        WalkRng rng = walk_rng(wi, wo);
        for (uint32_t sample = 0; sample < m->sample_count; ++sample) {
            BsdfSample wos, wis, rs;
            if (!coating_sample(m, wo, &rng, 1, LOBE_TRANSMISSION, &wos) ||
                !coating_sample(m, wi, &rng, 0, LOBE_TRANSMISSION, &wis))
                continue;
            Vec3 down_out = v_scale(wos.wi, -1.0f), down_in = v_scale(wis.wi, -1.0f);
            if (coating_smooth) {
                layered_base_f(m, down_out, down_in, &pdf);
                sum += pdf;
                continue;
            }
            float u1 = walk_uniform(&rng), u2 = walk_uniform(&rng);
            if (!layered_base_sample(m, down_out, u1, u2, &rs) || v_max_component(rs.f) <= 0.0f)
                continue;
            float t_pdf = 0.0f;
            coating_f(m, v_scale(rs.wi, -1.0f), wi, LOBE_ALL, &t_pdf);
            if (base_smooth) {
                sum += t_pdf;
                continue;
            }
            float r_pdf = 0.0f;
            layered_base_f(m, down_out, down_in, &r_pdf);
            sum += power_heuristic(wis.pdf, r_pdf) * r_pdf + power_heuristic(rs.pdf, t_pdf) * t_pdf;
        }
    }
    return 0.1f / (4.0f * PI_F) + 0.9f * sum / (float)m->sample_count;
}

/* Keeps a sample's f / pdf (its path weight) but makes pdf the estimated
 * density (layered_pdf), so that MIS weighs it as next-event estimation
 * does: their weights then sum to 1 (pbrt-v4 does so for the walks' own
 * "proportional" samples; here also for a rough coating's reflection,
 * whose lobe density alone would not match). */
KERNEL_FN void layered_rescale(const Material *m, Vec3 wo, BsdfSample *s)
{
    float estimate = layered_pdf(m, wo, s->wi);
    s->f = v_scale(v_scale(s->f, 1.0f / s->pdf), estimate);
    s->pdf = estimate;
}

/* A direction by a random walk: reflection off the coating, or into the
 * layer and on until the walk leaves through the coating. */
KERNEL_FN int layered_sample(const Material *m, Vec3 wo, float u_lobe, float u1, float u2, BsdfSample *s)
{
    float flip = wo.z < 0.0f ? -1.0f : 1.0f;
    Vec3 up_wo = v_scale(wo, flip);
    if (!dielectric_sample(m->eta, m->alpha_x, m->alpha_y, up_wo, u_lobe, u1, u2, 1, LOBE_ALL, s) ||
        v_max_component(s->f) <= 0.0f || s->wi.z == 0.0f)
        return 0;
    if (!s->is_transmission) {
        if (!s->is_delta)
            layered_rescale(m, up_wo, s);
        s->wi = v_scale(s->wi, flip);
        return 1;
    }
    float thickness = m->thickness;
    int medium = layered_has_medium(m);
    Vec3 albedo = vec3_from(m->albedo);
    WalkRng rng = walk_rng(up_wo, vec3(u_lobe, u1, u2));
    Vec3 f = v_scale(s->f, -s->wi.z), w = s->wi;
    float pdf = s->pdf, z = thickness;
    for (uint32_t depth = 0; depth < m->max_depth; ++depth) {
        float ratio = v_max_component(f) / pdf;
        if (depth > 3 && ratio < 0.25f) {
            float q = 1.0f - ratio;
            if (walk_uniform(&rng) < q)
                return 0;
            pdf *= 1.0f - q;
        }
        if (w.z == 0.0f)
            return 0;
        if (medium) {
            float u = walk_uniform(&rng);
            float dz = -log_float(1.0f - u) * (w.z < 0.0f ? -w.z : w.z);
            float zp = w.z > 0.0f ? z + dz : z - dz;
            if (zp == z)
                return 0;
            if (zp > 0.0f && zp < thickness) {
                Vec3 back = v_scale(w, -1.0f);
                Vec3 next = hg_sample(back, m->g, walk_uniform(&rng), walk_uniform(&rng));
                float phase = hg_phase(back, next, m->g);
                if (!(phase > 0.0f) || next.z == 0.0f)
                    return 0;
                f = v_scale(v_mul(f, albedo), phase);
                pdf *= phase;
                w = next;
                z = zp;
                continue;
            }
            z = zp < 0.0f ? 0.0f : thickness;
        } else {
            z = z == thickness ? 0.0f : thickness;
            f = v_scale(f, layer_transmittance(thickness, w));
        }
        BsdfSample bs;
        Vec3 back = v_scale(w, -1.0f);
        int ok = z == 0.0f ? layered_base_sample(m, back, walk_uniform(&rng), walk_uniform(&rng), &bs)
                           : coating_sample(m, back, &rng, 1, LOBE_ALL, &bs);
        if (!ok || v_max_component(bs.f) <= 0.0f || !(bs.pdf > 0.0f) || bs.wi.z == 0.0f)
            return 0;
        f = v_mul(f, bs.f);
        pdf *= bs.pdf;
        w = bs.wi;
        if (bs.is_transmission) {
            /* Out through the coating. */
            s->wi = w;
            s->f = f;
            s->pdf = pdf;
            s->is_transmission = 0;
            s->etap = 1.0f;
            s->is_delta = layered_is_delta(m);
            if (!s->is_delta)
                layered_rescale(m, up_wo, s);
            s->wi = v_scale(s->wi, flip);
            return 1;
        }
        f = v_scale(f, w.z < 0.0f ? -w.z : w.z);
    }
    return 0;
}

/* ---- the material dispatch: evaluation f(wo, wi) and the pdf of sampling
 * wi (delta lobes give 0), and sampling ---- */

/* radiance: 1 for radiance transport (paths from the camera), 0 for
 * importance (light subpaths): only refraction differs, by etap^2. */
KERNEL_FN Vec3 bsdf_eval_transport(const Material *m, Vec3 wo, Vec3 wi, float *pdf, int radiance)
{
    *pdf = 0.0f;
    Vec3 zero = vec3(0.0f, 0.0f, 0.0f);
#if GMON_HAS_DIELECTRIC
    if (m->type == MAT_DIELECTRIC) {
        float value = dielectric_f(m->eta, m->alpha_x, m->alpha_y, wo, wi, radiance, LOBE_ALL, pdf);
        return vec3(value, value, value);
    }
#endif
#if GMON_HAS_THIN_DIELECTRIC
    if (m->type == MAT_THIN_DIELECTRIC)
        return zero;
#endif
#if GMON_HAS_DIFFUSE_TRANSMISSION
    if (m->type == MAT_DIFFUSE_TRANSMISSION)
        return diffuse_transmission_f(m, wo, wi, pdf);
#endif
#if GMON_HAS_LAYERED
    if (m->type == MAT_COATED_DIFFUSE || m->type == MAT_COATED_CONDUCTOR) {
        if (wo.z * wi.z <= 0.0f)
            return zero;
        *pdf = layered_pdf(m, wo, wi);
        return layered_f(m, wo, wi);
    }
#endif
    /* Reflection-only materials: two-sided. */
    if (wo.z < 0.0f) {
        wo.z = -wo.z;
        wi.z = -wi.z;
    }
    if (wi.z <= 0.0f || wo.z <= 0.0f)
        return zero;
#if GMON_HAS_CONDUCTOR
    if (m->type == MAT_CONDUCTOR)
        return conductor_f(m, m->alpha_x, m->alpha_y, wo, wi, pdf);
#endif
#if GMON_HAS_DIFFUSE
    *pdf = wi.z / PI_F;
    return v_scale(vec3_from(m->reflectance), 1.0f / PI_F);
#else
    return zero;
#endif
}

KERNEL_FN Vec3 bsdf_eval(const Material *m, Vec3 wo, Vec3 wi, float *pdf)
{
    return bsdf_eval_transport(m, wo, wi, pdf, 1);
}

/* radiance: as bsdf_eval_transport's. */
KERNEL_FN int bsdf_sample_transport(const Material *m, Vec3 wo, float u_lobe, float u1, float u2, BsdfSample *s,
                                    int radiance)
{
    bsdf_sample_clear(s);
    if (wo.z == 0.0f)
        return 0;
#if GMON_HAS_DIELECTRIC
    if (m->type == MAT_DIELECTRIC)
        return dielectric_sample(m->eta, m->alpha_x, m->alpha_y, wo, u_lobe, u1, u2, radiance, LOBE_ALL, s);
#endif
#if GMON_HAS_THIN_DIELECTRIC
    if (m->type == MAT_THIN_DIELECTRIC)
        return thin_dielectric_sample(m->eta, wo, u_lobe, s);
#endif
#if GMON_HAS_DIFFUSE_TRANSMISSION
    if (m->type == MAT_DIFFUSE_TRANSMISSION)
        return diffuse_transmission_sample(m, wo, u_lobe, u1, u2, s);
#endif
#if GMON_HAS_LAYERED
    if (m->type == MAT_COATED_DIFFUSE || m->type == MAT_COATED_CONDUCTOR)
        return layered_sample(m, wo, u_lobe, u1, u2, s);
#endif

    /* Reflection-only: sample above the surface, mirror back if needed. */
    float flip = wo.z < 0.0f ? -1.0f : 1.0f;
    Vec3 up_wo = vec3(wo.x, wo.y, wo.z * flip);
#if GMON_HAS_CONDUCTOR
    if (m->type == MAT_CONDUCTOR) {
        if (!conductor_sample(m, m->alpha_x, m->alpha_y, up_wo, u1, u2, s))
            return 0;
        s->wi.z *= flip;
        return 1;
    }
#endif
#if GMON_HAS_DIFFUSE
    Vec3 wi = cosine_hemisphere(u1, u2);
    if (wi.z <= 0.0f)
        return 0;
    s->wi = vec3(wi.x, wi.y, wi.z * flip);
    s->f = bsdf_eval(m, wo, s->wi, &s->pdf);
    return s->pdf > 0.0f;
#else
    return 0;
#endif
}

KERNEL_FN int bsdf_sample(const Material *m, Vec3 wo, float u_lobe, float u1, float u2, BsdfSample *s)
{
    return bsdf_sample_transport(m, wo, u_lobe, u1, u2, s, 1);
}

/* ---- mix: one of two materials, materials[1] with chance `amount`, picked
 * by a hash of the hit point and direction (as pbrt-v4's MixMaterial), so
 * that the same hit always sees the same material: next-event estimation
 * and the BSDF sample of a hit use the same BSDF, and the mixture is
 * unbiased. amount 0 or 1 takes its material without the hash. ---- */

/* One mix's component for `amount` (its own or its texture's at the hit). */
KERNEL_FN const GLOBAL Material *mix_choose(const GLOBAL Material *materials, const GLOBAL Material *m, float amount,
                                            Vec3 p, Vec3 wo)
{
    int pick = amount >= 1.0f;
    if (amount > 0.0f && amount < 1.0f) {
        WalkRng hash = walk_rng(p, wo);
        pick = rng_uniform(hash.key, (uint32_t)(m - materials)) < amount;
    }
    return materials + m->mix_materials[pick];
}

KERNEL_FN const GLOBAL Material *mix_resolve(const GLOBAL Material *materials, const GLOBAL Material *m, Vec3 p,
                                             Vec3 wo)
{
    for (int level = 0; level < MIX_MAX_NESTING && m->type == MAT_MIX; ++level)
        m = mix_choose(materials, m, m->mix_amount, p, wo);
    return m;
}

/* Whether every lobe of m is a delta (no next-event estimation there). */
KERNEL_FN int bsdf_is_delta(const Material *m)
{
    if ((GMON_HAS_DIFFUSE_TRANSMISSION && m->type == MAT_DIFFUSE_TRANSMISSION) || m->type == MAT_DIFFUSE)
        return 0;
    if (GMON_HAS_THIN_DIELECTRIC && m->type == MAT_THIN_DIELECTRIC)
        return 1;
    if (GMON_HAS_LAYERED && (m->type == MAT_COATED_DIFFUSE || m->type == MAT_COATED_CONDUCTOR))
        return layered_is_delta(m);
    return m->alpha_x < SMOOTH_ALPHA && m->alpha_y < SMOOTH_ALPHA;
}

#endif
