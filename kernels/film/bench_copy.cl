/* The practical bandwidth limit for benchmarks: copies floats, one float4
 * per work item, reading and writing the same bytes an estimator reads. */
__kernel void copy_float4(__global const float4 *in, __global float4 *out, ulong count)
{
    ulong i = get_global_id(0);
    if (i < count)
        out[i] = in[i];
}
