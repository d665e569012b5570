/* Checks a scene's values before anything is built: ranges of numbers and
 * integers (one table each), names from fixed sets, the combinations
 * (frame_interval >= dt, a file for the file generator and none for the
 * others, some mass) and the
 * colliders (colliders.c), and the run's size: at most SB_SCENE_MAX_STEPS
 * steps (duration / dt) and SB_SCENE_MAX_FRAMES frames (duration /
 * frame_interval), so that a run's loop counts fit their integers and a
 * typo such as dt: 1e-30 is refused at once instead of running for ever,
 * and a generated sheet has at most SB_SCENE_MAX_SHEET_VERTICES vertices
 * (2^24: a 4096 x 4096 sheet; 30000 x 30000 would take 20 GB).
 * Vertex indices are checked when the mesh is known (scene_model.c). */
#include "scenes/scene.h"
#include "scenes/colliders.h"
#include "scenes/frame_formats.h"
#include "scenes/handles.h"
#include "scenes/blades.h"
#include "scenes/haptics.h"
#include "scenes/pin.h"
#include "scenes/scene_model.h"
#include "scenes/suggest.h"

#include <math.h>
#include <string.h>

enum { SB_SCENE_MAX_FRAMES = 1000000, SB_SCENE_MAX_SHEET_VERTICES = 1 << 24 };
#define SB_SCENE_MAX_STEPS 1e10

typedef struct number_rule {
    sb_scene_key key;
    bool positive; /* > 0; otherwise >= 0 */
} number_rule;

static const number_rule number_rules[] = {
    {SB_KEY_MESH_WIDTH, true},
    {SB_KEY_MESH_HEIGHT, true},
    {SB_KEY_MESH_JITTER, false},
    {SB_KEY_MESH_RADIUS, true},
    {SB_KEY_BOND_K, false},
    {SB_KEY_ANGLE_K, false},
    {SB_KEY_STRETCH_BEND_K, false},
    {SB_KEY_SPRING_K, false},
    {SB_KEY_SPRING_DAMPING, false},
    {SB_KEY_BEND_K, false},
    {SB_KEY_BOND_BREAK_STRAIN, false},
    {SB_KEY_MASS, false},
    {SB_KEY_DENSITY, false},
    {SB_KEY_DT, true},
    {SB_KEY_DURATION, true},
    {SB_KEY_FRAME_INTERVAL, true},
    {SB_KEY_DRAG, false},
    {SB_KEY_MIN_DT, true},
    {SB_KEY_IMPLICIT_TOLERANCE, true},
    {SB_KEY_SPRINGS_STRETCH_K, false},
    {SB_KEY_SPRINGS_STRETCH_DAMPING, false},
    {SB_KEY_SPRINGS_BEND_K, false},
    {SB_KEY_SPRINGS_BEND_DAMPING, false},
    {SB_KEY_SPRINGS_VICINITY_DISTANCE, false},
    {SB_KEY_SPRINGS_VICINITY_K, false},
    {SB_KEY_SPRINGS_VICINITY_DAMPING, false},
    {SB_KEY_SPRINGS_BREAK_STRAIN, false},
    {SB_KEY_TISSUE_YOUNG_MODULUS, false},
    {SB_KEY_TISSUE_DENSITY, true},
    {SB_KEY_TISSUE_DAMPING, false},
    {SB_KEY_SHEET_YOUNG_MODULUS, true},
    {SB_KEY_SHEET_THICKNESS, true},
    {SB_KEY_SHEET_DENSITY, true},
    {SB_KEY_SHEET_STIFFNESS_DAMPING, false},
    {SB_KEY_TISSUE_STIFFNESS_DAMPING, false},
    {SB_KEY_MESH_TARGET_ERROR, false},
    {SB_KEY_CONTACT_THICKNESS, false},
    {SB_KEY_STOP_KINETIC_ENERGY, false},
    {SB_KEY_STOP_MIN_TIME, false},
    {SB_KEY_STOP_MAX_TIME, false},
    {SB_KEY_VBD_CHEBYSHEV_RHO, false},
    {SB_KEY_VBD_RELAXATION, true},
};

typedef struct integer_rule {
    sb_scene_key key;
    int64_t min, max;
} integer_rule;

static const integer_rule integer_rules[] = {
    {SB_KEY_MESH_NX, 2, 1 << 16},
    {SB_KEY_MESH_NY, 2, 1 << 16},
    {SB_KEY_MESH_SEED, 0, INT64_MAX},
    {SB_KEY_MESH_SUBDIVISIONS, 0, 8},
    {SB_KEY_THREADS, 0, SB_MAX_THREADS},
    {SB_KEY_MESH_TARGET_VERTICES, 0, UINT32_MAX},
    {SB_KEY_IMPLICIT_NEWTON_ITERATIONS, 1, 1000},
    {SB_KEY_IMPLICIT_CG_ITERATIONS, 1, 100000},
    {SB_KEY_PBD_ITERATIONS, 1, 100000},
    {SB_KEY_TEARING_MAX_SPLITS, -1, INT32_MAX},
    {SB_KEY_TEARING_MAX_SPLITS_PER_STEP, 0, INT32_MAX},
    {SB_KEY_VBD_ITERATIONS, 1, 100000},
};

static sb_status check_number(const sb_scene* scene, const number_rule* rule, sb_error* err) {
    double value = sb_scene_number(scene, rule->key);
    const char* name = sb_scene_key_get(rule->key)->name;
    if (!isfinite(value)) return sb_scene_fail(scene, rule->key, err, "'%s' must be finite, got %g", name, value);
    if (rule->positive ? value <= 0.0 : value < 0.0)
        return sb_scene_fail(scene, rule->key, err, "'%s' must be %s 0, got %g", name,
                             rule->positive ? ">" : ">=", value);
    return SB_OK;
}

static sb_status check_integer(const sb_scene* scene, const integer_rule* rule, sb_error* err) {
    int64_t value = sb_scene_integer(scene, rule->key);
    if (value >= rule->min && value <= rule->max) return SB_OK;
    return sb_scene_fail(scene, rule->key, err, "'%s' must be in [%lld, %lld], got %lld",
                         sb_scene_key_get(rule->key)->name, (long long)rule->min, (long long)rule->max,
                         (long long)value);
}

static sb_status check_ranges(const sb_scene* scene, sb_error* err) {
    for (size_t i = 0; i < sizeof number_rules / sizeof number_rules[0]; i++) {
        sb_status status = check_number(scene, &number_rules[i], err);
        if (status != SB_OK) return status;
    }
    for (size_t i = 0; i < sizeof integer_rules / sizeof integer_rules[0]; i++) {
        sb_status status = check_integer(scene, &integer_rules[i], err);
        if (status != SB_OK) return status;
    }
    double rho = sb_scene_number(scene, SB_KEY_VBD_CHEBYSHEV_RHO); /* >= 0 checked above */
    if (rho >= 1.0)
        return sb_scene_fail(scene, SB_KEY_VBD_CHEBYSHEV_RHO, err,
                             "'vbd.chebyshev_rho' must be less than 1 (a spectral radius), got %g", rho);
    double relaxation = sb_scene_number(scene, SB_KEY_VBD_RELAXATION); /* > 0 checked above */
    if (relaxation >= 2.0)
        return sb_scene_fail(scene, SB_KEY_VBD_RELAXATION, err,
                             "'vbd.relaxation' must be less than 2 (successive over-relaxation), got %g", relaxation);
    return SB_OK;
}

static bool one_of(const char* value, const char* const* names) {
    for (; *names; names++)
        if (strcmp(value, *names) == 0) return true;
    return false;
}

/* " (did you mean ...?)" for a value of `key` against the names of `list`. */
static const char* hint(const sb_scene* scene, sb_scene_key key, const char* list) {
    static char text[128];
    return sb_suggest_hint(sb_scene_string(scene, key), list, text, sizeof text);
}

static sb_status check_names(const sb_scene* scene, sb_error* err) {
    static const char* const generators[] = {"sheet", "icosphere", "file", NULL};
    static const char* const kernels[] = {"reference", "fast", NULL};
    sb_integrator integrator;
    if (!one_of(sb_scene_string(scene, SB_KEY_MESH_GENERATOR), generators))
        return sb_scene_fail(scene, SB_KEY_MESH_GENERATOR, err,
                             "'mesh.generator' must be sheet, icosphere or file, got '%s'%s",
                             sb_scene_string(scene, SB_KEY_MESH_GENERATOR),
                             hint(scene, SB_KEY_MESH_GENERATOR, "sheet, icosphere, file"));
    static const char* const diagonals[] = {"auto", "alternating", "parallel", NULL};
    if (!one_of(sb_scene_string(scene, SB_KEY_MESH_DIAGONALS), diagonals))
        return sb_scene_fail(scene, SB_KEY_MESH_DIAGONALS, err,
                             "'mesh.diagonals' must be auto, alternating or parallel, got '%s'%s",
                             sb_scene_string(scene, SB_KEY_MESH_DIAGONALS),
                             hint(scene, SB_KEY_MESH_DIAGONALS, "auto, alternating, parallel"));
    if (!one_of(sb_scene_string(scene, SB_KEY_KERNELS), kernels))
        return sb_scene_fail(scene, SB_KEY_KERNELS, err, "'kernels' must be reference or fast, got '%s'%s",
                             sb_scene_string(scene, SB_KEY_KERNELS), hint(scene, SB_KEY_KERNELS, "reference, fast"));
    sb_linear_solver linear;
    if (!sb_linear_solver_from_name(sb_scene_string(scene, SB_KEY_IMPLICIT_SOLVER), &linear))
        return sb_scene_fail(
            scene, SB_KEY_IMPLICIT_SOLVER, err, "'implicit.solver' must be auto, cg or cholesky, got '%s'%s",
            sb_scene_string(scene, SB_KEY_IMPLICIT_SOLVER), hint(scene, SB_KEY_IMPLICIT_SOLVER, "auto, cg, cholesky"));
    sb_wait_policy wait;
    if (!sb_wait_policy_from_name(sb_scene_string(scene, SB_KEY_WAIT), &wait))
        return sb_scene_fail(scene, SB_KEY_WAIT, err, "'wait' must be spin, yield or passive, got '%s'%s",
                             sb_scene_string(scene, SB_KEY_WAIT), hint(scene, SB_KEY_WAIT, "spin, yield, passive"));
    if (!sb_integrator_from_name(sb_scene_string(scene, SB_KEY_INTEGRATOR), &integrator))
        return sb_scene_fail(scene, SB_KEY_INTEGRATOR, err,
                             "'integrator' must be verlet, velocity_verlet, position_verlet, "
                             "symplectic_euler, explicit_euler, implicit_euler, pbd, xpbd or vbd, got '%s'%s",
                             sb_scene_string(scene, SB_KEY_INTEGRATOR),
                             hint(scene, SB_KEY_INTEGRATOR,
                                  "verlet, velocity_verlet, position_verlet, symplectic_euler, explicit_euler, "
                                  "implicit_euler, pbd, xpbd, vbd"));
    static const char* const factories[] = {"molecular", "springs", "net", "membrane", NULL};
    static const char* const materials[] = {"liver", "gallbladder", NULL};
    if (!one_of(sb_scene_string(scene, SB_KEY_FACTORY), factories))
        return sb_scene_fail(
            scene, SB_KEY_FACTORY, err, "'factory' must be molecular, springs, net or membrane, got '%s'%s",
            sb_scene_string(scene, SB_KEY_FACTORY), hint(scene, SB_KEY_FACTORY, "molecular, springs, net, membrane"));
    if (!one_of(sb_scene_string(scene, SB_KEY_MATERIAL), materials))
        return sb_scene_fail(scene, SB_KEY_MATERIAL, err, "'material' must be liver or gallbladder, got '%s'%s",
                             sb_scene_string(scene, SB_KEY_MATERIAL),
                             hint(scene, SB_KEY_MATERIAL, "liver, gallbladder"));
    static const char* const tissue_models[] = {"auto", "springs", "corotated", "corotated_quadratic", NULL};
    if (!one_of(sb_scene_string(scene, SB_KEY_TISSUE_MODEL), tissue_models))
        return sb_scene_fail(scene, SB_KEY_TISSUE_MODEL, err,
                             "'tissue.model' must be auto, springs, corotated or corotated_quadratic, got '%s'%s",
                             sb_scene_string(scene, SB_KEY_TISSUE_MODEL),
                             hint(scene, SB_KEY_TISSUE_MODEL, "auto, springs, corotated, corotated_quadratic"));
    double nu = sb_scene_number(scene, SB_KEY_TISSUE_POISSON_RATIO);
    if (!(nu > -1.0 && nu < 0.5))
        return sb_scene_fail(scene, SB_KEY_TISSUE_POISSON_RATIO, err,
                             "'tissue.poisson_ratio' must be in (-1, 0.5), got %g", nu);
    double sheet_nu = sb_scene_number(scene, SB_KEY_SHEET_POISSON_RATIO);
    if (!(sheet_nu > -1.0 && sheet_nu < 0.5))
        return sb_scene_fail(scene, SB_KEY_SHEET_POISSON_RATIO, err,
                             "'sheet.poisson_ratio' must be in (-1, 0.5), got %g", sheet_nu);
    if (!sb_pin_known(sb_scene_string(scene, SB_KEY_PIN)))
        return sb_scene_fail(scene, SB_KEY_PIN, err, "'pin' must be one of %s, got '%s'%s", sb_pin_names(),
                             sb_scene_string(scene, SB_KEY_PIN), hint(scene, SB_KEY_PIN, sb_pin_names()));
    static const char* const vtu[] = {"ascii", "binary", "zlib", NULL};
    if (!one_of(sb_scene_string(scene, SB_KEY_OUTPUT_VTU), vtu))
        return sb_scene_fail(scene, SB_KEY_OUTPUT_VTU, err, "'output.vtu' must be ascii, binary or zlib, got '%s'%s",
                             sb_scene_string(scene, SB_KEY_OUTPUT_VTU),
                             hint(scene, SB_KEY_OUTPUT_VTU, "ascii, binary, zlib"));
    sb_frame_formats formats;
    char bad[64];
    if (!sb_frame_formats_parse(sb_scene_string(scene, SB_KEY_OUTPUT_FORMATS), &formats, bad, sizeof bad)) {
        char near[96];
        return sb_scene_fail(scene, SB_KEY_OUTPUT_FORMATS, err, "'output.formats': %s%s%s (known: %s)%s",
                             bad[0] ? "unknown format '" : "an empty format name", bad, bad[0] ? "'" : "",
                             sb_frame_formats_known(),
                             sb_suggest_hint(bad, sb_frame_formats_known(), near, sizeof near));
    }
    return SB_OK;
}

/* The key to blame for a combination: the one the user set, if any. */
static sb_scene_key blame(const sb_scene* scene, sb_scene_key first, sb_scene_key second) {
    return scene->values[first].where[0] ? first : second;
}

/* The vectors (placement, gravity, load): finite, and no zero scale. */
static sb_status check_vectors(const sb_scene* scene, sb_error* err) {
    static const sb_scene_key keys[] = {SB_KEY_MESH_SCALE, SB_KEY_MESH_ROTATE, SB_KEY_MESH_TRANSLATE,
                                        SB_KEY_GRAVITY,    SB_KEY_LOAD_FORCE,  SB_KEY_LOAD_AT};
    for (size_t i = 0; i < sizeof keys / sizeof keys[0]; i++) {
        const double* v = sb_scene_vec3(scene, keys[i]);
        const char* name = sb_scene_key_get(keys[i])->name;
        for (int k = 0; k < 3; k++) {
            if (!isfinite(v[k])) return sb_scene_fail(scene, keys[i], err, "'%s' must be finite", name);
            if (keys[i] == SB_KEY_MESH_SCALE && v[k] == 0.0)
                return sb_scene_fail(scene, keys[i], err, "'%s' must not be 0 (the mesh would collapse)", name);
        }
    }
    return SB_OK;
}

/* The key to blame for a count: one set by --set (the last word), else
 * one set in the file, else the first. */
static sb_scene_key blame_count(const sb_scene* scene, sb_scene_key first, sb_scene_key second) {
    if (strncmp(scene->values[second].where, "--set", 5) == 0) return second;
    if (strncmp(scene->values[first].where, "--set", 5) == 0) return first;
    return blame(scene, first, second);
}

/* duration / dt steps, duration / frame_interval frames and a generated
 * sheet's nx * ny vertices, each bounded. */
static sb_status check_counts(const sb_scene* scene, sb_error* err) {
    double duration = sb_scene_number(scene, SB_KEY_DURATION);
    double dt = sb_scene_number(scene, SB_KEY_DT);
    double interval = sb_scene_number(scene, SB_KEY_FRAME_INTERVAL);
    if (!(duration / dt <= SB_SCENE_MAX_STEPS))
        return sb_scene_fail(scene, blame_count(scene, SB_KEY_DT, SB_KEY_DURATION), err,
                             "'duration' (%g) / 'dt' (%g) is %.3g steps, more than the limit of %.0e", duration, dt,
                             duration / dt, SB_SCENE_MAX_STEPS);
    if (!(duration / interval <= SB_SCENE_MAX_FRAMES))
        return sb_scene_fail(scene, blame_count(scene, SB_KEY_FRAME_INTERVAL, SB_KEY_DURATION), err,
                             "'duration' (%g) / 'frame_interval' (%g) is %.3g frames, more than the limit of %d",
                             duration, interval, duration / interval, SB_SCENE_MAX_FRAMES);
    int64_t nx = sb_scene_integer(scene, SB_KEY_MESH_NX), ny = sb_scene_integer(scene, SB_KEY_MESH_NY);
    if (strcmp(sb_scene_string(scene, SB_KEY_MESH_GENERATOR), "sheet") == 0 && nx * ny > SB_SCENE_MAX_SHEET_VERTICES)
        return sb_scene_fail(scene, blame_count(scene, SB_KEY_MESH_NX, SB_KEY_MESH_NY), err,
                             "'mesh.nx' x 'mesh.ny' is %lld vertices, more than the limit of %d", (long long)(nx * ny),
                             SB_SCENE_MAX_SHEET_VERTICES);
    return SB_OK;
}

static sb_status check_combinations(const sb_scene* scene, sb_error* err) {
    sb_status vectors = check_vectors(scene, err);
    if (vectors != SB_OK) return vectors;
    if (sb_scene_number(scene, SB_KEY_MESH_JITTER) >= 0.5)
        return sb_scene_fail(scene, SB_KEY_MESH_JITTER, err, "'mesh.jitter' must be < 0.5");
    double dt = sb_scene_number(scene, SB_KEY_DT);
    double interval = sb_scene_number(scene, SB_KEY_FRAME_INTERVAL);
    if (interval < dt)
        return sb_scene_fail(scene, blame(scene, SB_KEY_FRAME_INTERVAL, SB_KEY_DT), err,
                             "'frame_interval' (%g) must be >= 'dt' (%g)", interval, dt);
    sb_status counts = check_counts(scene, err);
    if (counts != SB_OK) return counts;
    if (sb_scene_number(scene, SB_KEY_MASS) == 0.0 && sb_scene_number(scene, SB_KEY_DENSITY) == 0.0)
        return sb_scene_fail(scene, blame(scene, SB_KEY_MASS, SB_KEY_DENSITY), err,
                             "'mass' and 'density' are both 0: free vertices need a mass");
    bool file = strcmp(sb_scene_string(scene, SB_KEY_MESH_GENERATOR), "file") == 0;
    if (file && sb_scene_string(scene, SB_KEY_MESH_FILE)[0] == '\0')
        return sb_scene_fail(scene, SB_KEY_MESH_GENERATOR, err, "'mesh.generator' is file but 'mesh.file' is not set");
    if (!file && sb_scene_string(scene, SB_KEY_MESH_FILE)[0] != '\0')
        return sb_scene_fail(scene, SB_KEY_MESH_FILE, err,
                             "'mesh.file' has no effect: 'mesh.generator' is %s (set mesh.generator: file to load "
                             "the file)",
                             sb_scene_string(scene, SB_KEY_MESH_GENERATOR));
    bool sheet = strcmp(sb_scene_string(scene, SB_KEY_MESH_GENERATOR), "sheet") == 0;
    if (strcmp(sb_scene_string(scene, SB_KEY_FACTORY), "net") == 0 &&
        (!sheet || sb_scene_bool(scene, SB_KEY_MESH_REORDER) || sb_scene_lod(scene)))
        return sb_scene_fail(scene, SB_KEY_FACTORY, err,
                             "'factory' net needs mesh.generator sheet, not renumbered or simplified (its bonds "
                             "follow the sheet's rows and columns)");
    if (sb_scene_bool(scene, SB_KEY_SELF_COLLISION) && !(sb_scene_number(scene, SB_KEY_CONTACT_THICKNESS) > 0.0))
        return sb_scene_fail(scene, blame(scene, SB_KEY_SELF_COLLISION, SB_KEY_CONTACT_THICKNESS), err,
                             "'self_collision' needs 'contact.thickness' > 0 (the distance kept between surfaces)");
    return SB_OK;
}

sb_status sb_scene_validate(const sb_scene* scene, sb_error* err) {
    sb_status status = check_ranges(scene, err);
    if (status == SB_OK) status = check_names(scene, err);
    if (status == SB_OK) status = check_combinations(scene, err);
    if (status == SB_OK) status = sb_scene_colliders_check(scene, err);
    if (status == SB_OK) status = sb_scene_handles_check(scene, err);
    if (status == SB_OK) status = sb_scene_blades_check(scene, err);
    if (status == SB_OK) status = sb_scene_haptics_check(scene, err);
    return status;
}
