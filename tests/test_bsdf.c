/* BSDFs (kernels/bsdf.h, compiled on the host): sampling agrees with
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
        m.conductor_eta[c] = 0.2f + 0.3f * (float)c; /* gold-like spread */
        m.conductor_k[c] = 3.0f - 0.5f * (float)c;
    }
    return m;
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

static void check_material(const Case *c)
{
    TestRng rng = test_rng(99);
    const float cosines[] = {0.95f, 0.6f, 0.2f, -0.5f};
    for (size_t k = 0; k < sizeof cosines / sizeof cosines[0]; ++k) {
        Vec3 wo = direction(cosines[k], 0.7f);
        const int n = 200000;
        int successes = 0;
        double energy = 0.0;
        for (int i = 0; i < n; ++i) {
            BsdfSample s;
            if (!bsdf_sample(&c->material, wo, (float)test_rng_uniform(&rng), (float)test_rng_uniform(&rng),
                             (float)test_rng_uniform(&rng), &s))
                continue;
            ++successes;
            assert_true(s.pdf > 0.0f && isfinite(s.f.x) && s.f.x >= 0.0f);
            /* Energy, not radiance: undo the 1/eta^2 of transmission. */
            energy += (double)s.f.y * fabs(s.wi.z) / s.pdf * (double)(s.etap * s.etap);
            if (!s.is_delta) {
                float pdf = 0.0f;
                Vec3 f = bsdf_eval(&c->material, wo, s.wi, &pdf);
                if (fabsf(pdf - s.pdf) > 1e-3f * s.pdf || fabsf(f.x - s.f.x) > 1e-3f * s.f.x)
                    fail_msg("%s: sample and eval disagree at wo.z=%g: pdf %g vs %g, f %g vs %g", c->name, (double)wo.z,
                             (double)s.pdf, (double)pdf, (double)s.f.x, (double)f.x);
            }
        }
        energy /= n;
        /* The density's integral equals the chance that sampling returns a
         * direction (for lobes that are not delta); estimated on a jittered
         * grid over the sphere, which keeps peaked lobes' variance low. */
        double integral = 0.0;
        int has_delta = c->material.type != MAT_DIFFUSE && c->material.alpha_x < SMOOTH_ALPHA;
        const int grid = 1000;
        for (int i = 0; i < grid && !has_delta; ++i)
            for (int j = 0; j < grid; ++j) {
                float z = 1.0f - 2.0f * ((float)i + (float)test_rng_uniform(&rng)) / (float)grid;
                float phi = 2.0f * PI_F * ((float)j + (float)test_rng_uniform(&rng)) / (float)grid;
                float pdf = 0.0f;
                bsdf_eval(&c->material, wo, direction(z, phi), &pdf);
                integral += pdf * 4.0 * PI_F;
            }
        integral /= (double)grid * grid;
        double success_rate = (double)successes / n;
        printf("  %-28s wo.z=%5.2f  energy %.4f  success %.4f  pdf integral %s%.4f\n", c->name, (double)wo.z, energy,
               success_rate, has_delta ? "(delta) " : "", has_delta ? success_rate : integral);
        assert_true(energy <= 1.0 + 0.01);
        if (c->material.type == MAT_DIFFUSE)
            assert_true(fabs(energy - 0.7) < 0.01);
        if (c->material.type == MAT_DIELECTRIC && c->material.alpha_x < SMOOTH_ALPHA)
            assert_true(fabs(energy - 1.0) < 1e-4); /* smooth glass loses nothing */
        if (!has_delta)
            assert_true(fabs(integral - success_rate) < 0.01);
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
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i)
        check_material(&cases[i]);
}

static void test_reflection_is_reciprocal(void **state)
{
    (void)state;
    TestRng rng = test_rng(5);
    const Material materials[] = {make(MAT_CONDUCTOR, 0.3f, 1.0f), make(MAT_DIELECTRIC, 0.3f, 1.5f),
                                  make(MAT_COATED_DIFFUSE, 0.2f, 1.5f), make(MAT_DIFFUSE, 0, 1)};
    for (size_t m = 0; m < sizeof materials / sizeof materials[0]; ++m)
        for (int i = 0; i < 1000; ++i) {
            Vec3 a = uniform_sphere(&rng), b = uniform_sphere(&rng);
            if (a.z * b.z <= 0.0f)
                continue; /* reflection only: transmission scales by eta^2 */
            float pdf;
            Vec3 fab = bsdf_eval(&materials[m], a, b, &pdf), fba = bsdf_eval(&materials[m], b, a, &pdf);
            assert_true(fabsf(fab.x - fba.x) <= 1e-4f * (fab.x > 1.0f ? fab.x : 1.0f));
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
        cmocka_unit_test(test_materials),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
