/* BSDFs (kernels/tracing/bsdf.h, compiled on the host): sampling agrees with
 * evaluation, the sampling density integrates to the chance of a sample,
 * energy is conserved, and reflection is reciprocal. */
#include "bsdf.h"
#include "sample_streams.h"

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

static Material make(uint32_t type, float alpha, float eta)
{
    Material m;
    memset(&m, 0, sizeof m);
    m.type = type;
    m.alpha_x = m.alpha_y = alpha;
    m.eta = eta;
    for (int c = 0; c < 3; ++c) {
        m.reflectance[c] = 0.7f;
        m.transmittance[c] = 0.2f;
        m.conductor_eta[c] = 0.2f + 0.3f * (float)c; /* gold-like spread */
        m.conductor_k[c] = 3.0f - 0.5f * (float)c;
    }
    m.base_alpha_x = m.base_alpha_y = alpha > 0.0f ? 0.2f : 0.0f;
    /* pbrt-v4's layered defaults */
    m.thickness = 0.01f;
    m.max_depth = 10;
    m.sample_count = 1;
    return m;
}

/* A layered material with a medium between its layers. */
static Material with_medium(Material m, float albedo, float g)
{
    m.albedo[0] = m.albedo[1] = m.albedo[2] = albedo;
    m.g = g;
    m.thickness = 0.1f;
    return m;
}

static int is_layered(const Material *m)
{
    return m->type == MAT_COATED_DIFFUSE || m->type == MAT_COATED_CONDUCTOR;
}

typedef struct {
    const char *name;
    Material material;
} Case;

static Vec3 direction(float cos_theta, float phi)
{
    float s = sqrtf(1.0f - cos_theta * cos_theta);
    return vec3(s * cosf(phi), s * sinf(phi), cos_theta);
}

static Vec3 uniform_sphere(TestRng *rng)
{
    float z = 1.0f - 2.0f * (float)test_rng_uniform(rng);
    return direction(z, 6.2831853f * (float)test_rng_uniform(rng));
}

/* The chance that sampling m returns a delta direction, from wo. */
static double delta_chance(const Material *m, Vec3 wo)
{
    float cos_o = fabsf(wo.z);
    if (m->type == MAT_THIN_DIELECTRIC)
        return 1.0;
    if (is_layered(m) && m->alpha_x < SMOOTH_ALPHA)
        return layered_is_delta(m) ? 1.0 : fresnel_dielectric(cos_o, m->eta);
    return m->type != MAT_DIFFUSE && m->type != MAT_DIFFUSE_TRANSMISSION && !is_layered(m) && m->alpha_x < SMOOTH_ALPHA
               ? 1.0
               : 0.0;
}

static void check_material(const Case *c)
{
    TestRng rng = test_rng(99);
    const float cosines[] = {0.95f, 0.6f, 0.2f, -0.5f};
    const Material *m = &c->material;
    for (size_t k = 0; k < sizeof cosines / sizeof cosines[0]; ++k) {
        Vec3 wo = direction(cosines[k], 0.7f);
        const int n = is_layered(m) ? 50000 : 200000;
        int successes = 0;
        double energy = 0.0, radiance = 0.0, delta_radiance = 0.0;
        for (int i = 0; i < n; ++i) {
            BsdfSample s;
            if (!bsdf_sample(m, wo, (float)test_rng_uniform(&rng), (float)test_rng_uniform(&rng),
                             (float)test_rng_uniform(&rng), &s))
                continue;
            ++successes;
            assert_true(s.pdf > 0.0f && isfinite(s.f.x) && s.f.x >= 0.0f);
            /* Energy, not radiance: undo the 1/eta^2 of transmission. */
            energy += (double)s.f.y * fabs(s.wi.z) / s.pdf * (double)(s.etap * s.etap);
            radiance += (double)s.f.y * fabs(s.wi.z) / s.pdf;
            if (s.is_delta)
                delta_radiance += (double)s.f.y * fabs(s.wi.z) / s.pdf;
            if (!s.is_delta && !is_layered(m)) {
                float pdf = 0.0f;
                Vec3 f = bsdf_eval(&c->material, wo, s.wi, &pdf);
                if (fabsf(pdf - s.pdf) > 1e-3f * s.pdf || fabsf(f.x - s.f.x) > 1e-3f * s.f.x)
                    fail_msg("%s: sample and eval disagree at wo.z=%g: pdf %g vs %g, f %g vs %g", c->name, (double)wo.z,
                             (double)s.pdf, (double)pdf, (double)s.f.x, (double)f.x);
            }
        }
        energy /= n;
        radiance /= n;
        delta_radiance /= n;
        /* The density's integral equals the chance that sampling returns a
         * direction (for lobes that are not delta), and the integral of
         * f |cos| the radiance sampling returns from the non-delta lobes;
         * both estimated on a jittered grid over the sphere, which keeps
         * peaked lobes' variance low. (The layered materials' density is an
         * estimate: only f is checked for them.) */
        double integral = 0.0, reflected = 0.0;
        double delta = delta_chance(m, wo);
        const int grid = is_layered(m) ? 300 : 1000;
        for (int i = 0; i < grid && delta < 1.0; ++i)
            for (int j = 0; j < grid; ++j) {
                float z = 1.0f - 2.0f * ((float)i + (float)test_rng_uniform(&rng)) / (float)grid;
                float phi = 2.0f * PI_F * ((float)j + (float)test_rng_uniform(&rng)) / (float)grid;
                float pdf = 0.0f;
                Vec3 f = bsdf_eval(m, wo, direction(z, phi), &pdf);
                integral += pdf * 4.0 * PI_F;
                reflected += f.y * fabsf(z) * 4.0 * PI_F;
            }
        integral /= (double)grid * grid;
        reflected /= (double)grid * grid;
        double success_rate = (double)successes / n;
        printf("  %-32s wo.z=%5.2f  energy %.4f  success %.4f  pdf integral %s%.4f  f cos integral %.4f vs %.4f\n",
               c->name, (double)wo.z, energy, success_rate, delta >= 1.0 ? "(delta) " : "",
               delta >= 1.0 ? success_rate : integral, reflected, radiance - delta_radiance);
        assert_true(energy <= 1.0 + 0.01);
        if (m->type == MAT_DIFFUSE)
            assert_true(fabs(energy - 0.7) < 0.01);
        if (m->type == MAT_DIFFUSE_TRANSMISSION)
            assert_true(fabs(energy - 0.9) < 0.01); /* reflectance + transmittance */
        if ((m->type == MAT_DIELECTRIC && m->alpha_x < SMOOTH_ALPHA) || m->type == MAT_THIN_DIELECTRIC)
            assert_true(fabs(energy - 1.0) < 1e-4); /* smooth glass loses nothing */
        if (delta < 1.0 && !is_layered(m))
            assert_true(fabs(integral - success_rate) < 0.01);
        /* Evaluation and sampling agree on the non-delta lobes' radiance;
         * the layered ones are random walks, within their noise. */
        if (delta < 1.0)
            assert_true(fabs(reflected - (radiance - delta_radiance)) < (is_layered(m) ? 0.02 : 0.01));
    }
}

static void test_materials(void **state)
{
    (void)state;
    const Case cases[] = {
        {"diffuse", make(MAT_DIFFUSE, 0.0f, 1.0f)},
        {"smooth dielectric", make(MAT_DIELECTRIC, 0.0f, 1.5f)},
        {"rough dielectric a=0.3", make(MAT_DIELECTRIC, 0.3f, 1.5f)},
        {"rough dielectric a=0.12", make(MAT_DIELECTRIC, 0.12f, 1.33f)},
        {"smooth conductor", make(MAT_CONDUCTOR, 0.0f, 1.0f)},
        {"rough conductor a=0.2", make(MAT_CONDUCTOR, 0.2f, 1.0f)},
        {"smooth coated diffuse", make(MAT_COATED_DIFFUSE, 0.0f, 1.5f)},
        {"rough coated diffuse a=0.3", make(MAT_COATED_DIFFUSE, 0.3f, 1.5f)},
        {"coated diffuse, medium", with_medium(make(MAT_COATED_DIFFUSE, 0.3f, 1.5f), 0.8f, 0.5f)},
        {"smooth coated conductor", make(MAT_COATED_CONDUCTOR, 0.0f, 1.5f)},
        {"rough coated conductor a=0.3", make(MAT_COATED_CONDUCTOR, 0.3f, 1.5f)},
        {"coated conductor, medium", with_medium(make(MAT_COATED_CONDUCTOR, 0.3f, 1.5f), 0.5f, -0.3f)},
        {"diffuse transmission", make(MAT_DIFFUSE_TRANSMISSION, 0.0f, 1.0f)},
        {"thin dielectric", make(MAT_THIN_DIELECTRIC, 0.0f, 1.5f)},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i)
        check_material(&cases[i]);
}

static void test_reflection_is_reciprocal(void **state)
{
    (void)state;
    TestRng rng = test_rng(5);
    Material layered[] = {make(MAT_COATED_DIFFUSE, 0.2f, 1.5f), make(MAT_COATED_CONDUCTOR, 0.3f, 1.5f),
                          with_medium(make(MAT_COATED_DIFFUSE, 0.3f, 1.5f), 0.8f, 0.5f)};
    const Material materials[] = {make(MAT_CONDUCTOR, 0.3f, 1.5f),
                                  make(MAT_DIELECTRIC, 0.3f, 1.5f),
                                  make(MAT_DIFFUSE, 0, 1),
                                  make(MAT_DIFFUSE_TRANSMISSION, 0, 1),
                                  layered[0],
                                  layered[1],
                                  layered[2]};
    for (size_t m = 0; m < sizeof materials / sizeof materials[0]; ++m) {
        /* A layered BSDF is a random estimate: reciprocal in expectation, so
         * estimated with many walks and compared within their noise. */
        Material material = materials[m];
        int stochastic = is_layered(&material);
        if (stochastic)
            material.sample_count = 4096;
        double largest = 0.0;
        for (int i = 0; i < (stochastic ? 40 : 1000); ++i) {
            Vec3 a = uniform_sphere(&rng), b = uniform_sphere(&rng);
            if (a.z * b.z <= 0.0f)
                continue; /* reflection only: transmission scales by eta^2 */
            float pdf;
            Vec3 fab = bsdf_eval(&material, a, b, &pdf), fba = bsdf_eval(&material, b, a, &pdf);
            double difference = fabs(fab.x - fba.x) / (fab.x > 1.0f ? fab.x : 1.0f);
            largest = difference > largest ? difference : largest;
            assert_true(difference <= (stochastic ? 0.02 * (fab.x > 0.05f ? 1.0 : 0.1) + 0.002 : 1e-4));
        }
        printf("  material type %u: largest |f(a, b) - f(b, a)| %.5f\n", material.type, largest);
    }
}

/* Fresnel reflectance of a dielectric, in double, written from the
 * textbook formulas (not the code under test). */
static double fresnel_reference(double cos_i, double eta)
{
    if (cos_i < 0.0) {
        eta = 1.0 / eta;
        cos_i = -cos_i;
    }
    double sin2_t = (1.0 - cos_i * cos_i) / (eta * eta);
    if (sin2_t >= 1.0)
        return 1.0;
    double cos_t = sqrt(1.0 - sin2_t);
    double rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t), rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    return 0.5 * (rs * rs + rp * rp);
}

/* A smooth coating over a Lambertian base of albedo rho with nothing
 * between them has the closed form (adding-doubling of the two layers)
 * f = rho T(wo) T(wi) / (pi eta^2 (1 - rho r_in)), T = 1 - Fresnel, r_in
 * the coating's hemispherical reflectance from inside (total internal
 * reflection included), here by quadrature. */
static void test_smooth_coated_diffuse_closed_form(void **state)
{
    (void)state;
    const double eta = 1.5, rho = 0.6;
    double r_in = 0.0;
    const int steps = 200000;
    for (int i = 0; i < steps; ++i) {
        double mu = (i + 0.5) / steps; /* cos theta inside; 2 mu d mu is the cosine-weighted measure */
        r_in += fresnel_reference(-mu, eta) * 2.0 * mu / steps;
    }
    Material m = make(MAT_COATED_DIFFUSE, 0.0f, (float)eta);
    m.reflectance[0] = m.reflectance[1] = m.reflectance[2] = (float)rho;
    m.thickness = 1e-6f; /* no attenuation between the layers */
    m.max_depth = 200;
    m.sample_count = 20000;
    const float cosines[][2] = {{0.9f, 0.8f}, {0.5f, 0.7f}, {0.25f, 0.95f}};
    for (size_t k = 0; k < sizeof cosines / sizeof cosines[0]; ++k) {
        Vec3 wo = direction(cosines[k][0], 0.3f), wi = direction(cosines[k][1], 2.0f);
        float pdf = 0.0f;
        double f = bsdf_eval(&m, wo, wi, &pdf).y;
        double expected = rho * (1.0 - fresnel_reference(wo.z, eta)) * (1.0 - fresnel_reference(wi.z, eta)) /
                          (PI_F * eta * eta * (1.0 - rho * r_in));
        printf("  smooth coated diffuse cos %.2f, %.2f: f %.5f closed form %.5f (r_in %.4f)\n", (double)wo.z,
               (double)wi.z, f, expected, r_in);
        assert_true(fabs(f - expected) < 0.01 * expected);
    }
}

/* A thin slab reflects R + T^2 R / (1 - R^2) = 2R / (1 + R) of the light. */
static void test_thin_dielectric_reflectance(void **state)
{
    (void)state;
    Material m = make(MAT_THIN_DIELECTRIC, 0.0f, 1.5f);
    const float cosines[] = {1.0f, 0.5f, -0.3f};
    for (size_t k = 0; k < sizeof cosines / sizeof cosines[0]; ++k) {
        Vec3 wo = direction(cosines[k], 0.4f);
        double r = fresnel_reference(fabs(wo.z), 1.5), expected = 2.0 * r / (1.0 + r);
        BsdfSample s;
        assert_true(bsdf_sample(&m, wo, 0.0f, 0.5f, 0.5f, &s)); /* u_lobe 0: the reflection */
        assert_true(s.is_delta && !s.is_transmission && s.wi.z == wo.z);
        assert_true(fabs(s.pdf - expected) < 1e-6);
        assert_true(bsdf_sample(&m, wo, 0.9999f, 0.5f, 0.5f, &s));
        assert_true(s.is_transmission && s.wi.x == -wo.x && s.wi.z == -wo.z && s.etap == 1.0f);
        assert_true(fabs(s.pdf - (1.0 - expected)) < 1e-6);
    }
}

/* The phase function integrates to 1 and its sampling has its mean cosine g. */
static void test_henyey_greenstein(void **state)
{
    (void)state;
    TestRng rng = test_rng(3);
    const float gs[] = {0.0f, 0.6f, -0.4f};
    Vec3 wo = direction(0.3f, 1.0f);
    for (size_t k = 0; k < sizeof gs / sizeof gs[0]; ++k) {
        double integral = 0.0, mean_cos = 0.0;
        const int n = 400000;
        for (int i = 0; i < n; ++i) {
            integral += hg_phase(wo, uniform_sphere(&rng), gs[k]) * 4.0 * PI_F;
            Vec3 wi = hg_sample(wo, gs[k], (float)test_rng_uniform(&rng), (float)test_rng_uniform(&rng));
            mean_cos += -v_dot(wo, wi); /* cosine to the forward direction */
        }
        integral /= n;
        mean_cos /= n;
        printf("  HG g=%.2f: integral %.4f, mean cosine %.4f\n", (double)gs[k], integral, mean_cos);
        assert_true(fabs(integral - 1.0) < 0.02);
        assert_true(fabs(mean_cos - gs[k]) < 0.005);
    }
}

/* A mix picks materials[1] with chance amount over hit points, and its
 * component outright at amount 0 or 1. */
static void test_mix_choice(void **state)
{
    (void)state;
    Material materials[3];
    materials[0] = make(MAT_DIFFUSE, 0, 1);
    materials[1] = make(MAT_CONDUCTOR, 0.2f, 1);
    materials[2] = make(MAT_MIX, 0, 1);
    materials[2].mix_materials[0] = 0;
    materials[2].mix_materials[1] = 1;
    TestRng rng = test_rng(8);
    const float amounts[] = {0.0f, 0.3f, 1.0f};
    for (size_t k = 0; k < sizeof amounts / sizeof amounts[0]; ++k) {
        materials[2].mix_amount = amounts[k];
        int second = 0;
        const int n = 100000;
        for (int i = 0; i < n; ++i) {
            Vec3 p = vec3((float)test_rng_uniform(&rng), (float)test_rng_uniform(&rng), 0.0f);
            Vec3 wo = uniform_sphere(&rng);
            const Material *chosen = mix_resolve(materials, &materials[2], p, wo);
            assert_true(chosen == &materials[0] || chosen == &materials[1]);
            assert_true(chosen == mix_resolve(materials, &materials[2], p, wo)); /* the same hit, the same choice */
            second += chosen == &materials[1];
        }
        printf("  mix amount %.1f: materials[1] %.4f of the time\n", (double)amounts[k], (double)second / n);
        assert_true(fabs((double)second / n - amounts[k]) < 0.006);
    }
}

static void test_fresnel_known_values(void **state)
{
    (void)state;
    /* Normal incidence on glass: ((1.5 - 1) / (1.5 + 1))^2 = 0.04. */
    assert_true(fabsf(fresnel_dielectric(1.0f, 1.5f) - 0.04f) < 1e-6f);
    /* Total internal reflection from inside beyond the critical angle. */
    assert_true(fresnel_dielectric(-0.3f, 1.5f) == 1.0f);
    /* A conductor with k = 0 is a dielectric. */
    assert_true(fabsf(fresnel_conductor(0.7f, 1.5f, 0.0f) - fresnel_dielectric(0.7f, 1.5f)) < 1e-6f);
    /* Normal incidence: ((n-1)^2 + k^2) / ((n+1)^2 + k^2). */
    float expected = ((0.2f - 1) * (0.2f - 1) + 9.0f) / ((0.2f + 1) * (0.2f + 1) + 9.0f);
    assert_true(fabsf(fresnel_conductor(1.0f, 0.2f, 3.0f) - expected) < 1e-5f);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_fresnel_known_values),
        cmocka_unit_test(test_reflection_is_reciprocal),
        cmocka_unit_test(test_smooth_coated_diffuse_closed_form),
        cmocka_unit_test(test_thin_dielectric_reflectance),
        cmocka_unit_test(test_henyey_greenstein),
        cmocka_unit_test(test_mix_choice),
        cmocka_unit_test(test_materials),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
