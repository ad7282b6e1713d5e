/* Spectra as pbrt-v4 reads them, reduced to the renderer's linear sRGB at
 * load (docs/scenes.md, "Spectra"). Every spectrum is resampled to
 * 1 nm steps over 360-830 nm, the grid pbrt-v4 integrates on. */
#ifndef HOST_SCENE_SPECTRUM_H
#define HOST_SCENE_SPECTRUM_H

#include <stddef.h>

#define SPECTRUM_LAMBDA_MIN 360
#define SPECTRUM_LAMBDA_MAX 830
#define SPECTRUM_SAMPLES (SPECTRUM_LAMBDA_MAX - SPECTRUM_LAMBDA_MIN + 1)
/* The sum of the CIE 1931 y matching function over the grid (pbrt-v4's CIE_Y_integral). */
#define SPECTRUM_CIE_Y_INTEGRAL 106.856895
#define SPECTRUM_DAYLIGHT_SAMPLES 107 /* S0, S1, S2 at 5 nm over 300-830 nm */
#define SPECTRUM_SWATCH_COUNT 24      /* ColorChecker swatches pbrt-v4 fits a sensor to */

typedef struct {
    double value[SPECTRUM_SAMPLES]; /* value[i] at 360 + i nm */
} Spectrum;

/* How a spectrum is reduced to RGB (the parameter's meaning in pbrt-v4). */
typedef enum {
    SPECTRUM_ILLUMINANT, /* emission: pbrt-v4's film value, normalised to luminance 1 */
    SPECTRUM_ALBEDO,     /* a reflectance in [0, 1], seen under the colour space's D65 */
    SPECTRUM_UNBOUNDED,  /* eta, k: a channel-weighted average of the values */
} SpectrumKind;

/* A tabulated spectrum: `count` (wavelength, value) pairs, interleaved. */
typedef struct {
    const char *name;
    const float *pairs;
    size_t count;
} NamedSpectrumTable;

/* A table entry of interleaved float pairs named `name`. */
#define SPECTRUM_TABLE(name, pairs)                                                                                    \
    {                                                                                                                  \
        name, pairs, sizeof pairs / sizeof pairs[0] / 2                                                                \
    }

/* Data (spectrum_data.c; spectrum_cie_data.c: the CMFs, the daylight basis
 * and the illuminants, stdillum-* and illum-acesD60). */
extern const float spectrum_cie_x[SPECTRUM_SAMPLES], spectrum_cie_y[SPECTRUM_SAMPLES], spectrum_cie_z[SPECTRUM_SAMPLES];
extern const float spectrum_daylight_s0[SPECTRUM_DAYLIGHT_SAMPLES], spectrum_daylight_s1[SPECTRUM_DAYLIGHT_SAMPLES],
    spectrum_daylight_s2[SPECTRUM_DAYLIGHT_SAMPLES];
extern const NamedSpectrumTable spectrum_cie_illuminants[], spectrum_named_tables[];
extern const size_t spectrum_cie_illuminant_count, spectrum_named_table_count;
/* spectrum_sensor_data.c: the camera sensors' <name>_r/_g/_b responses, the
 * ColorChecker swatches and the sRGB reflectance basis (red, green, blue). */
extern const NamedSpectrumTable spectrum_sensor_tables[], spectrum_swatch_tables[SPECTRUM_SWATCH_COUNT],
    spectrum_srgb_basis_tables[3];
extern const size_t spectrum_sensor_table_count;

/* Piecewise-linear interpolation of (lambda, value) pairs onto the grid.
 * Outside the first and last wavelengths the end values hold when
 * hold_ends (pbrt-v4's named and inline spectra), else the spectrum is 0
 * (its .spd files). Wavelengths must increase strictly. */
void spectrum_from_pairs(const double *lambda, const double *value, size_t count, int hold_ends, Spectrum *out);

/* Planck's law at `kelvin` (> 0), divided by its peak (pbrt-v4's blackbody). */
void spectrum_blackbody(double kelvin, Spectrum *out);

/* That blackbody's linear sRGB, negative channels clipped to 0; all 0 at
 * 100 K or below (pbrt-v4's media emit nothing there). */
void spectrum_blackbody_srgb(double kelvin, double rgb[3]);

/* pbrt-v4's built-in spectra by name (metal-Au-eta, glass-BK7,
 * stdillum-D65, illum-acesD60, canon_eos_100d_r, ...; the illuminants
 * stdillum-* and illum-acesD60 normalised to luminance 1 as pbrt does).
 * Returns 0, or -1 for an unknown name. */
int spectrum_named(const char *name, Spectrum *out);

/* The CIE daylight illuminant D at `kelvin` (a blackbody below 4000 K), as
 * pbrt-v4's Spectra::D: for white balance. */
void spectrum_daylight(double kelvin, Spectrum *out);

/* Parses the text of an .spd file: pairs of numbers, '#' comments to the end
 * of a line. Returns 0, or -1 with the reason in `why`. */
int spectrum_parse_spd(const char *text, Spectrum *out, char *why, size_t why_size);

/* CIE XYZ of a spectrum (sums over the grid / SPECTRUM_CIE_Y_INTEGRAL). */
void spectrum_to_xyz(const Spectrum *s, double xyz[3]);

/* Linear sRGB for a spectrum of the given kind (docs/scenes.md, "Spectra").
 * ILLUMINANT: 0 luminance gives black. */
void spectrum_to_rgb(const Spectrum *s, SpectrumKind kind, double rgb[3]);

/* A conductor's RGB eta and k from its spectra (docs/scenes.md, "Spectra"): per
 * channel, eta is the channel-weighted average (as SPECTRUM_UNBOUNDED) and
 * k is chosen so that the Fresnel reflectance at normal incidence equals
 * the sRGB (SPECTRUM_ALBEDO) of the spectral one, held within [0, 0.999]
 * (k = 0 and eta solved instead where no k reaches it). */
void spectrum_conductor_rgb(const Spectrum *eta, const Spectrum *k, double eta_rgb[3], double k_rgb[3]);

/* A dielectric's single eta: the spectrum averaged with the y matching
 * function (pbrt-v4 disperses instead; docs/scenes.md). */
double spectrum_eta(const Spectrum *s);

/* Linear sRGB from XYZ and back, for pbrt-v4's sRGB colour space (its
 * primaries with the white of its D65 table). */
void spectrum_srgb_from_xyz(double m[3][3]);
void spectrum_xyz_from_srgb(double m[3][3]);

/* pbrt-v4's white balance (von Kries in Bradford LMS) from the white of
 * `illuminant` to the colour space's D65 white, acting on XYZ. */
void spectrum_white_balance(const Spectrum *illuminant, double m[3][3]);

/* Whether pbrt-v4 knows the sensor: "cie1931" or a camera with
 * <name>_r/_g/_b responses here (every camera pbrt-v4 names). */
int spectrum_sensor_known(const char *sensor);

/* The known sensors as "cie1931, canon_eos_100d, ...", into buf
 * (NUL-terminated, cut short when size is too small). */
void spectrum_sensor_list(char *buf, size_t size);

/* pbrt-v4's XYZFromSensorRGB for a camera sensor: the least-squares fit
 * from the sensor RGB of the 24 swatches under the daylight illuminant at
 * white_balance_kelvin (> 0) to their XYZ under D65 (PixelSensor).
 * Returns 0, or -1 for a sensor without responses. */
int spectrum_sensor_xyz_from_sensor_rgb(const char *sensor, double white_balance_kelvin, double m[3][3]);

/* A camera sensor's RGB for linear sRGB radiance: the sensor's response to
 * the spectrum that radiance stands for, D65 (luminance 1) times the sRGB
 * reflectance basis (docs/scenes.md, "The film's response"). Returns 0, or -1 as above. */
int spectrum_sensor_from_srgb(const char *sensor, double m[3][3]);

/* The film matrix of scene.h: imaging_ratio times sRGB-from-XYZ times
 * XYZ-from-sensor-RGB times sensor-RGB-from-sRGB. For "cie1931" the
 * sensor is XYZ and XYZ-from-sensor-RGB the white balance from the
 * daylight illuminant at white_balance_kelvin (0: none); for a camera,
 * spectrum_sensor_xyz_from_sensor_rgb at white_balance_kelvin (0: 6500 K,
 * pbrt-v4's default for a camera).
 * Returns 0, or -1 for an unknown sensor. */
int spectrum_film_from_radiance(const char *sensor, double imaging_ratio, double white_balance_kelvin, float m[3][3]);

#endif
