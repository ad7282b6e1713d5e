/* Texture programs evaluated at given points, for tests that compare the
 * device's evaluation with the host's (tests/test_textures.c): context i
 * is contexts[12 i ...] = p (3), n (3), u, v, footprint, uv density, and
 * out[3 i ...] the program's value there. */
#include "texture.h"

__kernel void texture_probe(__global const TextureNode *nodes, __global const uchar *bytes,
                            __global const float *floats, int first, __global const float *contexts,
                            __global float *out, uint count)
{
    uint i = get_global_id(0);
    if (i >= count)
        return;
    __global const float *in = contexts + 12 * (size_t)i;
    TextureContext c;
    c.p = vec3(in[0], in[1], in[2]);
    c.n = vec3(in[3], in[4], in[5]);
    c.u = in[6];
    c.v = in[7];
    c.footprint = in[8];
    c.uv_density = in[9];
    TextureArrays a;
    a.nodes = nodes;
    a.bytes = bytes;
    a.floats = floats;
    Vec3 v = texture_evaluate(&a, first, &c);
    out[3 * i] = v.x;
    out[3 * i + 1] = v.y;
    out[3 * i + 2] = v.z;
}
