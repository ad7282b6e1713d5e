#include "render/scene_upload.h"

#include <stdio.h>
#include <string.h>

void scene_upload_init(SceneUpload *u, const RenderScene *scene, uint32_t seed)
{
    memset(u, 0, sizeof *u);
    u->constants = scene->constants;
    u->constants.integrator.seed = seed;
    u->data[0] = &u->constants;
    u->bytes[0] = sizeof u->constants;
    RenderSceneArrays arrays = render_scene_arrays(scene);
#define SCENE_ARRAY_POINT(name, type)                                                                                  \
    u->data[1 + SCENE_ARRAY_##name] = arrays.name;                                                                     \
    u->bytes[1 + SCENE_ARRAY_##name] = arrays.name##_count * sizeof(type);
    GMON_SCENE_ARRAYS(SCENE_ARRAY_POINT)
#undef SCENE_ARRAY_POINT
}

size_t scene_upload_bytes(const SceneUpload *u)
{
    size_t total = 0;
    for (int i = 0; i < SCENE_BUFFERS; ++i)
        total += u->bytes[i] ? u->bytes[i] : sizeof(uint64_t);
    return total;
}

/* What each buffer holds, for messages. */
#define BUFFER(name) [1 + SCENE_ARRAY_##name]
static const char *const buffer_names[] = {
    [0] = "the constants",
    BUFFER(nodes) = "the BVH",
    BUFFER(primitives) = "the primitives",
    BUFFER(materials) = "the materials",
    BUFFER(lights) = "the lights",
    BUFFER(light_nodes) = "the light tree",
    BUFFER(light_trails) = "the light tree's trails",
    BUFFER(distributions) = "the image lights' sampling distributions",
    BUFFER(texels) = "image texels",
    BUFFER(shading_normals) = "the shading normals",
    BUFFER(textures) = "the texture programs",
    BUFFER(material_textures) = "the materials' texture table",
    BUFFER(texture_bytes) = "texture bytes",
    BUFFER(texture_floats) = "texture values",
    BUFFER(surface_uvs) = "the triangles' uvs",
    BUFFER(instances) = "the instances",
    BUFFER(alphas) = "the alpha table",
    BUFFER(media) = "the media",
    BUFFER(primitive_media) = "the media's interfaces",
    BUFFER(medium_values) = "the media's grids",
};
#undef BUFFER
_Static_assert(sizeof buffer_names / sizeof *buffer_names == SCENE_BUFFERS, "a name for each scene buffer");

void scene_upload_describe(const SceneUpload *u, int most, char *out, size_t size)
{
    int used[SCENE_BUFFERS] = {0};
    size_t length = 0;
    out[0] = '\0';
    for (int k = 0; k < most && length < size; ++k) {
        int largest = -1;
        for (int i = 0; i < SCENE_BUFFERS; ++i)
            if (!used[i] && u->bytes[i] > 0 && (largest < 0 || u->bytes[i] > u->bytes[largest]))
                largest = i;
        if (largest < 0)
            break;
        used[largest] = 1;
        const char *name = buffer_names[largest] ? buffer_names[largest] : "a scene array";
        double mib = (double)u->bytes[largest] / 1048576.0;
        int n = mib >= 1024.0
                    ? snprintf(out + length, size - length, "%s%s %.2f GiB", k ? ", " : "", name, mib / 1024.0)
                    : snprintf(out + length, size - length, "%s%s %.1f MiB", k ? ", " : "", name, mib);
        length += n > 0 ? (size_t)n : 0;
    }
}

static uint64_t fnv1a(uint64_t hash, const void *data, size_t size)
{
    const unsigned char *bytes = data;
    for (size_t i = 0; i < size; ++i)
        hash = (hash ^ bytes[i]) * 0x100000001b3ull;
    return hash;
}

void scene_upload_hash(const SceneUpload *u, int sets, char *hex, size_t size)
{
    uint64_t hash = 0xcbf29ce484222325ull;
    for (int i = 0; i < SCENE_BUFFERS; ++i)
        hash = fnv1a(hash, u->data[i], u->bytes[i]);
    hash = fnv1a(hash, &sets, sizeof sets);
    snprintf(hex, size, "%016llx", (unsigned long long)hash);
}

cl_int scene_upload_create(const SceneUpload *u, cl_context context, cl_kernel kernel, cl_mem buffers[SCENE_BUFFERS])
{
    static const uint64_t zero = 0; /* OpenCL refuses empty buffers */
    cl_int err = CL_SUCCESS;
    for (int i = 0; i < SCENE_BUFFERS && err == CL_SUCCESS; ++i) {
        size_t bytes = u->bytes[i];
        buffers[i] = clCreateBuffer(context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, bytes ? bytes : sizeof zero,
                                    bytes ? (void *)u->data[i] : (void *)&zero, &err);
        if (err == CL_SUCCESS)
            err = clSetKernelArg(kernel, (cl_uint)i, sizeof(cl_mem), &buffers[i]);
    }
    if (err != CL_SUCCESS)
        for (int i = 0; i < SCENE_BUFFERS; ++i) {
            if (buffers[i])
                clReleaseMemObject(buffers[i]);
            buffers[i] = NULL;
        }
    return err;
}

cl_int scene_upload_bind(cl_kernel kernel, const cl_mem buffers[SCENE_BUFFERS])
{
    cl_int err = CL_SUCCESS;
    for (int i = 0; i < SCENE_BUFFERS && err == CL_SUCCESS; ++i)
        err = clSetKernelArg(kernel, (cl_uint)i, sizeof(cl_mem), &buffers[i]);
    return err;
}

cl_int scene_upload_bind_pass(cl_kernel kernel, const RenderPassArguments *a)
{
    struct {
        size_t size;
        const void *value;
    } args[] = {
        {sizeof a->accumulators, &a->accumulators},
        {sizeof a->rejected, &a->rejected},
        {sizeof a->rays, &a->rays},
        {sizeof a->first_sample, &a->first_sample},
        {sizeof a->sample_count, &a->sample_count},
        {sizeof a->first_pixel, &a->first_pixel},
        {sizeof a->pixel_count, &a->pixel_count},
        {sizeof a->buffer_first_pixel, &a->buffer_first_pixel},
        {sizeof a->buffer_pixel_count, &a->buffer_pixel_count},
    };
    cl_int err = CL_SUCCESS;
    for (size_t i = 0; i < sizeof args / sizeof args[0] && err == CL_SUCCESS; ++i)
        err = clSetKernelArg(kernel, (cl_uint)(SCENE_BUFFERS + i), args[i].size, args[i].value);
    if (err == CL_SUCCESS && a->samples)
        err = clSetKernelArg(kernel, (cl_uint)(SCENE_BUFFERS + sizeof args / sizeof args[0]), sizeof a->samples,
                             &a->samples);
    return err;
}
