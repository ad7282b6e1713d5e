/* BSDFs in the local shading frame (normal = +z): Lambertian diffuse,
 * dielectric and conductor (smooth, or rough with the GGX / Trowbridge-Reitz
 * microfacet distribution and visible-normal sampling), and an approximate
 * coated diffuse. Shared by host (tests) and kernels.
 *
 * Values follow pbrt-v4's definitions (radiance transport: transmission is
 * divided by the squared relative index). Reflection-only materials are
 * two-sided: directions below the surface are mirrored above it. */
#ifndef KERNELS_BSDF_H
#define KERNELS_BSDF_H

#include "feature_mask.h"
#include "scene_types.h"
#include "vec3.h"

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
KERNEL_FN int material_is_smooth(const Material *m)
{
    return !GMON_HAS_ROUGH || (m->alpha_x < SMOOTH_ALPHA && m->alpha_y < SMOOTH_ALPHA);
}

KERNEL_FN Vec3 cosine_hemisphere(float u1, float u2)
{
    float r = sqrt_float(u1), phi = 2.0f * PI_F * u2;
    float z2 = 1.0f - u1;
    return vec3(r * cos_float(phi), r * sin_float(phi), sqrt_float(z2 > 0.0f ? z2 : 0.0f));
}

KERNEL_FN Vec3 conductor_fresnel(const Material *m, float cos_i)
{
    return vec3(fresnel_conductor(cos_i, m->conductor_eta[0], m->conductor_k[0]),
                fresnel_conductor(cos_i, m->conductor_eta[1], m->conductor_k[1]),
                fresnel_conductor(cos_i, m->conductor_eta[2], m->conductor_k[2]));
}

/* Probability that the coated diffuse samples its specular coat. */
KERNEL_FN float coat_pick(const Material *m, float cos_o)
{
    float f = fresnel_dielectric(cos_o, m->eta);
    return f < 0.1f ? 0.1f : (f > 0.9f ? 0.9f : f);
}

/* ---- evaluation: f(wo, wi) and the pdf of sampling wi; delta lobes give 0 ---- */

/* Microfacet reflection with Fresnel term `fresnel`, both in +z. */
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

KERNEL_FN Vec3 bsdf_eval(const Material *m, Vec3 wo, Vec3 wi, float *pdf)
{
    *pdf = 0.0f;
    Vec3 zero = vec3(0.0f, 0.0f, 0.0f);
#if GMON_HAS_DIELECTRIC
    if (m->type == MAT_DIELECTRIC) {
        if (material_is_smooth(m) || wo.z == 0.0f || wi.z == 0.0f)
            return zero;
        float ax = m->alpha_x, ay = m->alpha_y;
        int reflect = wo.z * wi.z > 0.0f;
        float etap = reflect ? 1.0f : (wo.z > 0.0f ? m->eta : 1.0f / m->eta);
        Vec3 wm = v_add(v_scale(wi, etap), wo);
        if (v_dot(wm, wm) == 0.0f)
            return zero;
        wm = v_normalize(wm);
        if (wm.z < 0.0f)
            wm = v_scale(wm, -1.0f);
        float wi_m = v_dot(wi, wm), wo_m = v_dot(wo, wm);
        if (wi_m * wi.z < 0.0f || wo_m * wo.z < 0.0f)
            return zero; /* back-facing microfacet */
        float r = fresnel_dielectric(wo_m, m->eta), t = 1.0f - r;
        float d = ggx_d(wm, ax, ay), g = ggx_g(wo, wi, ax, ay);
        if (reflect) {
            *pdf = ggx_visible_d(wo, wm, ax, ay) / (4.0f * (wo_m < 0.0f ? -wo_m : wo_m)) * r;
            float value = d * g * r / (4.0f * wi.z * wo.z);
            value = value < 0.0f ? -value : value;
            return vec3(value, value, value);
        }
        float denominator = wi_m + wo_m / etap;
        denominator *= denominator;
        *pdf = ggx_visible_d(wo, wm, ax, ay) * (wi_m < 0.0f ? -wi_m : wi_m) / denominator * t;
        float value = t * d * g * (wi_m * wo_m / (wi.z * wo.z * denominator));
        value = (value < 0.0f ? -value : value) / (etap * etap);
        return vec3(value, value, value);
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
    if (m->type == MAT_CONDUCTOR) {
        if (material_is_smooth(m))
            return zero;
        Vec3 wm = vec3(0.0f, 0.0f, 1.0f);
        float value = microfacet_reflection(wo, wi, m->alpha_x, m->alpha_y, &wm, pdf);
        return v_scale(conductor_fresnel(m, v_dot(wo, wm)), value);
    }
#endif
    Vec3 diffuse = v_scale(vec3_from(m->reflectance), 1.0f / PI_F);
#if GMON_HAS_COATED_DIFFUSE
    if (m->type == MAT_COATED_DIFFUSE) {
        /* Approximation: Fresnel-weighted coat over a Lambertian base. */
        float pick = coat_pick(m, wo.z);
        float transmitted = (1.0f - fresnel_dielectric(wo.z, m->eta)) * (1.0f - fresnel_dielectric(wi.z, m->eta));
        Vec3 f = v_scale(diffuse, transmitted);
        *pdf = (1.0f - pick) * wi.z / PI_F;
        if (!material_is_smooth(m)) {
            Vec3 wm = vec3(0.0f, 0.0f, 1.0f);
            float coat_pdf = 0.0f;
            float coat = microfacet_reflection(wo, wi, m->alpha_x, m->alpha_y, &wm, &coat_pdf);
            coat *= fresnel_dielectric(v_dot(wo, wm), m->eta);
            f = v_add(f, vec3(coat, coat, coat));
            *pdf += pick * coat_pdf;
        }
        return f;
    }
#endif
#if GMON_HAS_DIFFUSE
    *pdf = wi.z / PI_F;
    return diffuse;
#else
    return zero;
#endif
}

/* ---- sampling ---- */

KERNEL_FN int bsdf_sample(const Material *m, Vec3 wo, float u_lobe, float u1, float u2, BsdfSample *s)
{
    s->is_delta = 0;
    s->is_transmission = 0;
    s->etap = 1.0f;
    s->pdf = 0.0f;
    s->f = vec3(0.0f, 0.0f, 0.0f);
    if (wo.z == 0.0f)
        return 0;
#if GMON_HAS_DIELECTRIC
    if (m->type == MAT_DIELECTRIC) {
        if (material_is_smooth(m)) {
            float r = fresnel_dielectric(wo.z, m->eta), t = 1.0f - r;
            s->is_delta = 1;
            if (u_lobe < r) {
                s->wi = vec3(-wo.x, -wo.y, wo.z);
                s->pdf = r;
                float value = r / (wo.z < 0.0f ? -wo.z : wo.z);
                s->f = vec3(value, value, value);
                return 1;
            }
            if (!refract_about(wo, vec3(0.0f, 0.0f, 1.0f), m->eta, &s->etap, &s->wi))
                return 0;
            s->is_transmission = 1;
            s->pdf = t;
            float value = t / (s->wi.z < 0.0f ? -s->wi.z : s->wi.z) / (s->etap * s->etap);
            s->f = vec3(value, value, value);
            return 1;
        }
        Vec3 wm = ggx_sample_visible(wo, m->alpha_x, m->alpha_y, u1, u2);
        float r = fresnel_dielectric(v_dot(wo, wm), m->eta);
        if (u_lobe < r) {
            s->wi = reflect_about(wo, wm);
            if (s->wi.z * wo.z <= 0.0f)
                return 0;
        } else {
            float etap = 1.0f;
            if (!refract_about(wo, wm, m->eta, &etap, &s->wi) || s->wi.z * wo.z >= 0.0f || s->wi.z == 0.0f)
                return 0;
            s->is_transmission = 1;
            s->etap = etap;
        }
        s->f = bsdf_eval(m, wo, s->wi, &s->pdf);
        return s->pdf > 0.0f;
    }
#endif

    /* Reflection-only: sample above the surface, mirror back if needed. */
    float flip = wo.z < 0.0f ? -1.0f : 1.0f;
    Vec3 up_wo = vec3(wo.x, wo.y, wo.z * flip);
#if GMON_HAS_CONDUCTOR
    if (m->type == MAT_CONDUCTOR) {
        if (material_is_smooth(m)) {
            s->is_delta = 1;
            s->wi = vec3(-wo.x, -wo.y, wo.z);
            s->pdf = 1.0f;
            s->f = v_scale(conductor_fresnel(m, up_wo.z), 1.0f / up_wo.z);
            return 1;
        }
        Vec3 wm = ggx_sample_visible(up_wo, m->alpha_x, m->alpha_y, u1, u2);
        Vec3 wi = reflect_about(up_wo, wm);
        if (wi.z <= 0.0f)
            return 0;
        s->wi = vec3(wi.x, wi.y, wi.z * flip);
        s->f = bsdf_eval(m, wo, s->wi, &s->pdf);
        return s->pdf > 0.0f;
    }
#endif
#if GMON_HAS_COATED_DIFFUSE
    if (m->type == MAT_COATED_DIFFUSE) {
        float pick = coat_pick(m, up_wo.z);
        if (u_lobe < pick) {
            if (material_is_smooth(m)) {
                float r = fresnel_dielectric(up_wo.z, m->eta);
                s->is_delta = 1;
                s->wi = vec3(-wo.x, -wo.y, wo.z);
                s->pdf = pick;
                float value = r / up_wo.z;
                s->f = vec3(value, value, value);
                return 1;
            }
            Vec3 wm = ggx_sample_visible(up_wo, m->alpha_x, m->alpha_y, u1, u2);
            Vec3 wi = reflect_about(up_wo, wm);
            if (wi.z <= 0.0f)
                return 0;
            s->wi = vec3(wi.x, wi.y, wi.z * flip);
        } else {
            Vec3 wi = cosine_hemisphere(u1, u2);
            s->wi = vec3(wi.x, wi.y, wi.z * flip);
        }
        s->f = bsdf_eval(m, wo, s->wi, &s->pdf);
        return s->pdf > 0.0f;
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

#endif
