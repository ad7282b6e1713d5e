/* The materials: Material, MakeNamedMaterial and NamedMaterial, and each
 * material type's parameters. */
#include "scene/materials.h"

#include "scene/textures.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int add_material(Parser *p, const SceneMaterial *m)
{
    Scene *s = p->scene;
    if (scene_reserve((void **)&s->materials, &p->material_capacity, s->material_count + 1, sizeof *s->materials))
        return -1;
    s->materials[s->material_count] = *m;
    return (int)s->material_count++;
}

static void default_material(SceneMaterial *m)
{
    memset(m, 0, sizeof *m);
    m->type = SCENE_MATERIAL_DIFFUSE;
    for (int i = 0; i < SCENE_SLOT_COUNT; ++i)
        m->textures[i] = -1;
    m->reflectance[0] = m->reflectance[1] = m->reflectance[2] = 0.5f;
    m->eta = 1.5f;
    m->remap_roughness = 1;
    m->mix_amount = 0.5f;
    m->scale = 1.0f;
    m->thickness = 0.01f;
    m->max_depth = 10;
    m->sample_count = 1;
}

/* The current material's index, creating pbrt's default (diffuse 0.5) once. */
int current_material(Parser *p)
{
    if (p->state.material >= 0)
        return p->state.material;
    if (p->default_material < 0) {
        SceneMaterial m;
        default_material(&m);
        p->default_material = add_material(p, &m);
    }
    return p->default_material;
}

/* A material parameter that may be a texture: 1 when it is one (its
 * index in m->textures[slot]), 0 when not (read the constant), -1 error. */
static int read_slot(Parser *p, ParamList *params, SceneMaterial *m, SceneMaterialSlot slot, const char *name,
                     int is_spectrum)
{
    return scene_texture_param_late(&p->diag, p->scene, &p->texture_capacity, params, name, is_spectrum,
                                    &m->textures[slot]);
}

/* A spectrum parameter given by a texture or a constant. Returns 0 or -1. */
static int read_spectrum_slot(Parser *p, ParamList *params, SceneMaterial *m, SceneMaterialSlot slot, const char *name,
                              SpectrumKind kind, float rgb[3], int *given)
{
    int taken = read_slot(p, params, m, slot, name, 1);
    if (taken == 0)
        taken = params_get_spectrum(params, name, kind, rgb);
    if (given)
        *given = taken > 0;
    return taken < 0 ? -1 : 0;
}

/* Every material's bump and normal maps. Returns 0 or -1. */
static int read_bump(Parser *p, ParamList *params, SceneMaterial *m, int line)
{
    if (read_slot(p, params, m, SCENE_SLOT_DISPLACEMENT, "displacement", 0) < 0)
        return -1;
    params_ignore(params, "displacement"); /* a constant displacement changes nothing */
    return scene_texture_normal_map(&p->diag, p->scene, &p->texture_capacity, params, line,
                                    &m->textures[SCENE_SLOT_NORMAL_MAP]) < 0
               ? -1
               : 0;
}

/* "<prefix>roughness" or "<prefix>uroughness"/"<prefix>vroughness"
 * (pbrt-v4's names, prefix "" or "interface." / "conductor."; pbrt-v4
 * prefers u and v), each a constant or a float texture (m->textures' slots
 * `slot_u` and the one after it, for v). */
static int read_roughness(Parser *p, ParamList *params, SceneMaterial *m, const char *prefix, float roughness[2],
                          SceneMaterialSlot slot_u_index, int line)
{
    SceneMaterialSlot slot_v_index = (SceneMaterialSlot)(slot_u_index + 1);
    char names[3][64];
    snprintf(names[0], sizeof names[0], "%sroughness", prefix);
    snprintf(names[1], sizeof names[1], "%suroughness", prefix);
    snprintf(names[2], sizeof names[2], "%svroughness", prefix);
    int *slot_u = &m->textures[slot_u_index], *slot_v = &m->textures[slot_v_index];
    if (read_slot(p, params, m, slot_u_index, names[0], 0) < 0)
        return -1;
    *slot_v = *slot_u;
    if (read_slot(p, params, m, slot_u_index, names[1], 0) < 0 ||
        read_slot(p, params, m, slot_v_index, names[2], 0) < 0)
        return -1;
    float r = 0.0f;
    if (params_get_float(params, names[0], &r) < 0)
        return -1;
    roughness[0] = roughness[1] = r;
    int constant_u = params_get_float(params, names[1], &roughness[0]);
    int constant_v = params_get_float(params, names[2], &roughness[1]);
    if (constant_u < 0 || constant_v < 0)
        return -1;
    if (constant_u > 0)
        *slot_u = -1;
    if (constant_v > 0)
        *slot_v = -1;
    if (roughness[0] < 0.0f || roughness[1] < 0.0f)
        return scene_error(&p->diag, params->file, line, "%s: roughness must not be negative", params->owner);
    return 0;
}

static int read_eta(ParamList *params, const char *name, float *eta, int line, Parser *p)
{
    if (params_get_eta(params, name, eta) < 0)
        return -1;
    if (!(*eta > 0.0f))
        return scene_error(&p->diag, params->file, line, "%s: eta must be positive", params->owner);
    return 0;
}

/* A conductor's "<prefix>eta" and "<prefix>k", or "reflectance" instead;
 * each may be a spectrum texture. */
static int read_conductor(Parser *p, ParamList *params, const char *prefix, SceneMaterial *m, int line)
{
    char eta_name[64], k_name[64];
    snprintf(eta_name, sizeof eta_name, "%seta", prefix);
    snprintf(k_name, sizeof k_name, "%sk", prefix);
    int eta_texture = read_slot(p, params, m, SCENE_SLOT_CONDUCTOR_ETA, eta_name, 1);
    int k_texture = read_slot(p, params, m, SCENE_SLOT_CONDUCTOR_K, k_name, 1);
    float reflectance[3];
    int has_reflectance = 0;
    if (eta_texture < 0 || k_texture < 0 ||
        read_spectrum_slot(p, params, m, SCENE_SLOT_REFLECTANCE, "reflectance", SPECTRUM_ALBEDO, reflectance,
                           &has_reflectance))
        return -1;
    int has_eta_k = params_get_conductor(params, prefix, m->conductor_eta, m->conductor_k);
    if (has_eta_k < 0)
        return -1;
    has_eta_k |= eta_texture | k_texture;
    if (has_reflectance && has_eta_k)
        return scene_error(&p->diag, params->file, line, "%s: give either \"reflectance\" or \"%seta\" and \"%sk\"",
                           params->owner, prefix, prefix);
    m->use_reflectance = has_reflectance;
    if (has_reflectance)
        memcpy(m->reflectance, reflectance, sizeof reflectance);
    return 0;
}

/* The layered BSDF's parameters of the coated materials (pbrt-v4's
 * defaults: thickness 0.01, no medium, g 0, maxdepth 10, nsamples 1);
 * thickness, g and albedo may be textures. */
static int read_layers(ParamList *params, SceneMaterial *m, int line, Parser *p)
{
    if (read_slot(p, params, m, SCENE_SLOT_THICKNESS, "thickness", 0) < 0 ||
        read_slot(p, params, m, SCENE_SLOT_G, "g", 0) < 0 ||
        read_spectrum_slot(p, params, m, SCENE_SLOT_ALBEDO, "albedo", SPECTRUM_ALBEDO, m->albedo, NULL) ||
        params_get_float(params, "thickness", &m->thickness) < 0 || params_get_float(params, "g", &m->g) < 0 ||
        params_get_int(params, "maxdepth", &m->max_depth) < 0 ||
        params_get_int(params, "nsamples", &m->sample_count) < 0 ||
        params_get_bool(params, "remaproughness", &m->remap_roughness) < 0)
        return -1;
    if (!(m->thickness > 0.0f) || !(m->g > -1.0f && m->g < 1.0f) || m->max_depth < 1 || m->sample_count < 1 ||
        m->sample_count > 1024 || m->max_depth > 1024)
        return scene_error(&p->diag, params->file, line,
                           "%s: needs thickness > 0, -1 < g < 1, 1 <= maxdepth <= 1024 and 1 <= nsamples <= 1024",
                           params->owner);
    return 0;
}

/* How many mixes deep material `index` is (0: not a mix). Components come
 * before their mix, and their nesting is bounded when they are read. */
static int mix_nesting(const Scene *scene, int index)
{
    const SceneMaterial *m = &scene->materials[index];
    if (m->type != SCENE_MATERIAL_MIX)
        return 0;
    int a = mix_nesting(scene, m->mix_materials[0]), b = mix_nesting(scene, m->mix_materials[1]);
    return 1 + (a > b ? a : b);
}

/* "string materials" [ "a" "b" ]: two named materials defined before. */
static int read_mix(Parser *p, ParamList *params, int line, SceneMaterial *m)
{
    const Param *names = NULL;
    int found = params_get_array(params, "materials", PARAM_STRING, &names);
    if (found < 0)
        return -1;
    if (found == 0 || names->count != 2)
        return scene_error(&p->diag, params->file, line, "%s: needs \"string materials\" with two material names",
                           params->owner);
    for (int i = 0; i < 2; ++i) {
        m->mix_materials[i] = -1;
        for (size_t j = 0; j < p->named_count && m->mix_materials[i] < 0; ++j)
            if (p->named[j].defined && strcmp(p->named[j].name, names->strings[i]) == 0)
                m->mix_materials[i] = p->named[j].material;
        if (m->mix_materials[i] < 0)
            return scene_error(&p->diag, params->file, line, "%s: no material named \"%s\"", params->owner,
                               names->strings[i]);
        const SceneMaterial *component = &p->scene->materials[m->mix_materials[i]];
        if (component->type == SCENE_MATERIAL_INTERFACE)
            return scene_error(&p->diag, params->file, line, "%s: \"%s\" is an \"interface\", which a mix cannot hold",
                               params->owner, names->strings[i]);
        if (mix_nesting(p->scene, m->mix_materials[i]) >= SCENE_MIX_MAX_NESTING)
            return scene_error(&p->diag, params->file, line, "%s: mixes nested deeper than %d", params->owner,
                               SCENE_MIX_MAX_NESTING);
    }
    if (read_slot(p, params, m, SCENE_SLOT_MIX_AMOUNT, "amount", 0) < 0 ||
        params_get_float(params, "amount", &m->mix_amount) < 0)
        return -1;
    return 0;
}

/* Fills *m from a material type and its parameters. An unknown type is
 * unsupported; allow_unsupported substitutes grey diffuse, or for hair,
 * measured and subsurface a diffuse of their reflectance. */
static int parse_material(Parser *p, const char *type, ParamList *params, int line, SceneMaterial *m)
{
    default_material(m);
    if (read_bump(p, params, m, line))
        return -1;
    if (strcmp(type, "diffuse") == 0) {
        if (read_spectrum_slot(p, params, m, SCENE_SLOT_REFLECTANCE, "reflectance", SPECTRUM_ALBEDO, m->reflectance,
                               NULL))
            return -1;
    } else if (strcmp(type, "dielectric") == 0 || strcmp(type, "thindielectric") == 0) {
        m->type = type[0] == 't' ? SCENE_MATERIAL_THIN_DIELECTRIC : SCENE_MATERIAL_DIELECTRIC;
        if (read_slot(p, params, m, SCENE_SLOT_ETA, "eta", 0) < 0 || read_eta(params, "eta", &m->eta, line, p))
            return -1;
        if (m->type == SCENE_MATERIAL_DIELECTRIC &&
            (read_roughness(p, params, m, "", m->roughness, SCENE_SLOT_ROUGHNESS_U, line) ||
             params_get_bool(params, "remaproughness", &m->remap_roughness) < 0))
            return -1;
    } else if (strcmp(type, "conductor") == 0) {
        m->type = SCENE_MATERIAL_CONDUCTOR;
        memset(m->reflectance, 0, sizeof m->reflectance);
        if (read_conductor(p, params, "", m, line) ||
            read_roughness(p, params, m, "", m->roughness, SCENE_SLOT_ROUGHNESS_U, line) ||
            params_get_bool(params, "remaproughness", &m->remap_roughness) < 0)
            return -1;
    } else if (strcmp(type, "coateddiffuse") == 0) {
        m->type = SCENE_MATERIAL_COATED_DIFFUSE;
        if (read_spectrum_slot(p, params, m, SCENE_SLOT_REFLECTANCE, "reflectance", SPECTRUM_ALBEDO, m->reflectance,
                               NULL) ||
            read_eta(params, "eta", &m->eta, line, p) ||
            read_roughness(p, params, m, "", m->roughness, SCENE_SLOT_ROUGHNESS_U, line) ||
            read_layers(params, m, line, p))
            return -1;
    } else if (strcmp(type, "coatedconductor") == 0) {
        m->type = SCENE_MATERIAL_COATED_CONDUCTOR;
        memset(m->reflectance, 0, sizeof m->reflectance);
        if (read_eta(params, "interface.eta", &m->eta, line, p) ||
            read_roughness(p, params, m, "interface.", m->roughness, SCENE_SLOT_ROUGHNESS_U, line) ||
            read_conductor(p, params, "conductor.", m, line) ||
            read_roughness(p, params, m, "conductor.", m->base_roughness, SCENE_SLOT_BASE_ROUGHNESS_U, line) ||
            read_layers(params, m, line, p))
            return -1;
    } else if (strcmp(type, "diffusetransmission") == 0) {
        m->type = SCENE_MATERIAL_DIFFUSE_TRANSMISSION;
        float scale = 1.0f;
        m->reflectance[0] = m->reflectance[1] = m->reflectance[2] = 0.25f;
        m->transmittance[0] = m->transmittance[1] = m->transmittance[2] = 0.25f;
        if (read_spectrum_slot(p, params, m, SCENE_SLOT_REFLECTANCE, "reflectance", SPECTRUM_ALBEDO, m->reflectance,
                               NULL) ||
            read_spectrum_slot(p, params, m, SCENE_SLOT_TRANSMITTANCE, "transmittance", SPECTRUM_ALBEDO,
                               m->transmittance, NULL) ||
            params_get_float(params, "scale", &scale) < 0)
            return -1;
        /* Constants only: the kernel clamps each textured one, scaled, to
         * [0, 1] (as pbrt-v4 does every one). */
        int reflects = m->textures[SCENE_SLOT_REFLECTANCE] < 0, transmits = m->textures[SCENE_SLOT_TRANSMITTANCE] < 0;
        float most = 0.0f;
        for (int c = 0; c < 3; ++c)
            most = fmaxf(most, (reflects ? m->reflectance[c] : 0.0f) + (transmits ? m->transmittance[c] : 0.0f));
        if (!(scale >= 0.0f) || scale * most > 1.0f)
            return scene_error(&p->diag, params->file, line,
                               "%s: \"scale\" must not be negative nor scatter more than it receives", params->owner);
        m->scale = scale;
        for (int c = 0; c < 3; ++c) {
            m->reflectance[c] *= scale;
            m->transmittance[c] *= scale;
        }
    } else if (strcmp(type, "mix") == 0) {
        m->type = SCENE_MATERIAL_MIX;
        if (read_mix(p, params, line, m))
            return -1;
    } else if (strcmp(type, "interface") == 0 || type[0] == '\0' || strcmp(type, "none") == 0) {
        m->type = SCENE_MATERIAL_INTERFACE; /* pbrt-v4 takes "" and "none" as no material, as "interface" */
    } else if (strcmp(type, "hair") == 0 || strcmp(type, "measured") == 0 || strcmp(type, "subsurface") == 0) {
        if (scene_unsupported(&p->diag, params->file, line, "a diffuse of its \"reflectance\" (default 0.5) is used",
                              "Material \"%s\" is not supported", type))
            return -1;
        if (read_spectrum_slot(p, params, m, SCENE_SLOT_REFLECTANCE, "reflectance", SPECTRUM_ALBEDO, m->reflectance,
                               NULL))
            return -1;
        return 0; /* its other parameters mean nothing to the substitute */
    } else {
        return scene_unsupported(&p->diag, params->file, line, "grey diffuse (reflectance 0.5) is used instead",
                                 "Material \"%s\" is not supported (diffuse, dielectric, thindielectric, conductor, "
                                 "coateddiffuse, coatedconductor, diffusetransmission, mix, interface)",
                                 type);
    }
    return params_check_unused(params);
}

int on_material(Parser *p, Lexer *lex, const Token *d)
{
    Token type;
    ParamList params;
    int result = read_typed_directive(p, lex, d, "the material type", &type, &params);
    if (result == 0)
        result = require_world(p, lex, d, 1);
    char *type_name = result == 0 ? scene_strndup(type.text, type.length) : NULL;
    if (result == 0 && !type_name)
        result = out_of_memory(p, lex->path, d->line);
    SceneMaterial m;
    if (result == 0)
        result = parse_material(p, type_name, &params, d->line, &m);
    if (result == 0) {
        p->state.material = add_material(p, &m);
        if (p->state.material < 0)
            result = out_of_memory(p, lex->path, d->line);
    }
    free(type_name);
    params_free(&params);
    return result;
}

int on_make_named_material(Parser *p, Lexer *lex, const Token *d)
{
    Token name;
    ParamList params;
    int result = read_typed_directive(p, lex, d, "the material's name", &name, &params);
    if (result == 0)
        result = require_world(p, lex, d, 1);
    char *name_copy = result == 0 ? scene_strndup(name.text, name.length) : NULL;
    if (result == 0 && !name_copy)
        result = out_of_memory(p, lex->path, d->line);
    NamedMaterial *used_before = NULL; /* by a NamedMaterial before this definition */
    for (size_t i = 0; result == 0 && i < p->named_count; ++i)
        if (strcmp(p->named[i].name, name_copy) == 0) {
            if (p->named[i].defined)
                result =
                    scene_error(&p->diag, lex->path, d->line, "MakeNamedMaterial: \"%s\" is defined twice", name_copy);
            else
                used_before = &p->named[i];
        }
    const char *type = NULL;
    if (result == 0 && params_get_string(&params, "type", &type) < 0)
        result = -1;
    if (result == 0 && !type)
        result =
            scene_error(&p->diag, lex->path, d->line, "MakeNamedMaterial \"%s\": missing \"string type\"", name_copy);
    SceneMaterial m;
    if (result == 0)
        result = parse_material(p, type, &params, d->line, &m);
    if (result == 0 && used_before) {
        p->scene->materials[used_before->material] = m;
        used_before->defined = 1;
    } else if (result == 0) {
        int index = add_material(p, &m);
        if (index < 0 || scene_reserve((void **)&p->named, &p->named_capacity, p->named_count + 1, sizeof *p->named))
            result = out_of_memory(p, lex->path, d->line);
        else {
            p->named[p->named_count++] = (NamedMaterial){name_copy, index, 1, lex->path, d->line};
            name_copy = NULL;
        }
    }
    free(name_copy);
    params_free(&params);
    return result;
}

int on_named_material(Parser *p, Lexer *lex, const Token *d)
{
    Token name;
    if (require_world(p, lex, d, 1) || expect_string(p, lex, d, "the material's name", &name))
        return -1;
    for (size_t i = 0; i < p->named_count; ++i)
        if (token_is(&name, p->named[i].name)) {
            p->state.material = p->named[i].material;
            return 0;
        }
    /* Not defined yet: a slot for the definition to come (finish_named_materials). */
    SceneMaterial placeholder;
    default_material(&placeholder);
    char *name_copy = scene_strndup(name.text, name.length);
    int index = name_copy ? add_material(p, &placeholder) : -1;
    if (index < 0 || scene_reserve((void **)&p->named, &p->named_capacity, p->named_count + 1, sizeof *p->named)) {
        free(name_copy);
        return out_of_memory(p, lex->path, d->line);
    }
    p->named[p->named_count++] = (NamedMaterial){name_copy, index, 0, lex->path, d->line};
    p->state.material = index;
    return 0;
}

/* A NamedMaterial whose name the whole scene never defines is an error at
 * its line, as in pbrt-v4; in check mode with files missing the name may
 * be defined in one of them, so it is not. */
int finish_named_materials(Parser *p)
{
    if (files_missing(p))
        return 0;
    for (size_t i = 0; i < p->named_count; ++i)
        if (!p->named[i].defined)
            return scene_error(&p->diag, p->named[i].file, p->named[i].line,
                               "NamedMaterial: no material named \"%s\" is defined (MakeNamedMaterial) in the scene",
                               p->named[i].name);
    return 0;
}
