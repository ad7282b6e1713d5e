/* Points, vectors and transforms for the directives (geometry.c). */
#ifndef HOST_SCENE_GEOMETRY_H
#define HOST_SCENE_GEOMETRY_H

#include <cglm/cglm.h>

/* The point `in` through m, in double (divided by w unless it is 1). */
void transform_point(mat4 m, const float in[3], float out[3]);

/* The determinant of m's linear part, in double. */
double det3(mat4 m);

void cross_d(const double a[3], const double b[3], double out[3]);
double dot_d(const double a[3], const double b[3]);

/* Scales v to unit length; returns its length before. */
double normalize_d(double v[3]);

/* Whether m's linear part is a rotation (or reflection) times a uniform
 * scale; *scale receives that scale. */
int is_similarity(mat4 m, double *scale);

/* Whether m's bottom row is (0, 0, 0, 1). */
int is_affine(mat4 m);

/* m's inverse computed in double; -1 when m is singular or its inverse does
 * not fit a float. */
int invert_in_double(mat4 m, mat4 inverse);

/* Whether every coordinate of a world-space point is within the renderer's
 * range (SCENE_MAX_COORDINATE; false for NaN). */
int within_range(const float point[3]);

/* Whether a and b are equal entry for entry. */
int same_matrix(mat4 a, mat4 b);

/* A direction through m's linear part, in double. */
void transform_vector_d(mat4 m, const double v[3], double out[3]);

#endif
