/* Points, vectors and transforms for the directives, in double precision
 * where a float would overflow or lose a tiny scale. Matrices are cglm's
 * mat4, column-major ([column][row]). */
#include "scene/geometry.h"

#include "scene/scene.h"

#include <float.h>
#include <math.h>

void transform_point(mat4 m, const float in[3], float out[3])
{
    double x = in[0], y = in[1], z = in[2];
    double r[4];
    for (int row = 0; row < 4; ++row)
        r[row] = m[0][row] * x + m[1][row] * y + m[2][row] * z + m[3][row];
    double w = r[3];
    for (int k = 0; k < 3; ++k)
        out[k] = (float)(w == 1.0 ? r[k] : r[k] / w);
}

double det3(mat4 m)
{
    return (double)m[0][0] * ((double)m[1][1] * m[2][2] - (double)m[2][1] * m[1][2]) -
           (double)m[1][0] * ((double)m[0][1] * m[2][2] - (double)m[2][1] * m[0][2]) +
           (double)m[2][0] * ((double)m[0][1] * m[1][2] - (double)m[1][1] * m[0][2]);
}

void cross_d(const double a[3], const double b[3], double out[3])
{
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

double dot_d(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* Scales v to unit length; returns its length before. */
double normalize_d(double v[3])
{
    double length = sqrt(dot_d(v, v));
    for (int k = 0; length > 0.0 && k < 3; ++k)
        v[k] /= length;
    return length;
}

/* Whether m's linear part is a rotation (or reflection) times a uniform
 * scale; *scale receives that scale (the columns' mean length). */
int is_similarity(mat4 m, double *scale)
{
    double length[3], largest = 0.0;
    for (int c = 0; c < 3; ++c) {
        length[c] = sqrt((double)m[c][0] * m[c][0] + (double)m[c][1] * m[c][1] + (double)m[c][2] * m[c][2]);
        largest = fmax(largest, length[c]);
    }
    *scale = (length[0] + length[1] + length[2]) / 3.0;
    if (largest == 0.0)
        return 0;
    const double tolerance = 1e-4;
    for (int a = 0; a < 3; ++a) {
        int b = (a + 1) % 3;
        double dot = (double)m[a][0] * m[b][0] + (double)m[a][1] * m[b][1] + (double)m[a][2] * m[b][2];
        if (fabs(length[a] - length[b]) > tolerance * largest || fabs(dot) > tolerance * largest * largest)
            return 0;
    }
    return 1;
}

int is_affine(mat4 m)
{
    return m[0][3] == 0.0f && m[1][3] == 0.0f && m[2][3] == 0.0f && m[3][3] == 1.0f;
}

/* The inverse of m by Gauss-Jordan elimination in double (a float inverse
 * loses a camera's tiny Scale to underflow). Returns -1 when m is singular
 * or its inverse does not fit a float. */
int invert_in_double(mat4 m, mat4 inverse)
{
    double a[4][8]; /* [row][column]: m, then the identity */
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) {
            a[r][c] = m[c][r];
            a[r][c + 4] = r == c ? 1.0 : 0.0;
        }
    for (int c = 0; c < 4; ++c) {
        int pivot = c;
        for (int r = c + 1; r < 4; ++r)
            if (fabs(a[r][c]) > fabs(a[pivot][c]))
                pivot = r;
        if (a[pivot][c] == 0.0)
            return -1;
        for (int k = 0; k < 8; ++k) {
            double t = a[c][k];
            a[c][k] = a[pivot][k];
            a[pivot][k] = t;
        }
        double scale = 1.0 / a[c][c];
        for (int k = 0; k < 8; ++k)
            a[c][k] *= scale;
        for (int r = 0; r < 4; ++r) {
            double f = a[r][c];
            for (int k = 0; r != c && k < 8; ++k)
                a[r][k] -= f * a[c][k];
        }
    }
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) {
            if (!(fabs(a[r][c + 4]) <= FLT_MAX))
                return -1;
            inverse[c][r] = (float)a[r][c + 4];
        }
    return 0;
}

/* Whether every coordinate of a world-space point is within the renderer's
 * range (false for NaN). */
int within_range(const float point[3])
{
    return fabsf(point[0]) <= SCENE_MAX_COORDINATE && fabsf(point[1]) <= SCENE_MAX_COORDINATE &&
           fabsf(point[2]) <= SCENE_MAX_COORDINATE;
}

int same_matrix(mat4 a, mat4 b)
{
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            if (a[c][r] != b[c][r])
                return 0;
    return 1;
}

/* A direction through the CTM's linear part, in double. */
void transform_vector_d(mat4 m, const double v[3], double out[3])
{
    for (int k = 0; k < 3; ++k)
        out[k] = m[0][k] * v[0] + m[1][k] * v[1] + m[2][k] * v[2];
}
