/* `softbond eval MESH`: the energy of each enabled term (and optionally the
 * forces) of a mesh's model at its rest positions or at POS.csv, as one
 * JSON object on stdout. The mesh file's positions are the rest state; the
 * constants are the scene keys' defaults and --set. Double scalar reference
 * by default; --fast goes through a solver with the fast kernels. */
#include "common/atomic_file.h"
#include "cli/cli.h"
#include "common/error.h"
#include "cli/positions_csv.h"
#include "scenes/scene_model.h"

#include <stdlib.h>
#include <string.h>

void sb_cli_eval_usage(FILE* stream) {
    fprintf(stream, "usage: softbond eval MESH [--set key=value]... [--positions POS.csv]\n"
                    "                     [--forces OUT.csv] [--fast]\n"
                    "Builds the model of MESH (its positions are the rest state; constants from\n"
                    "the scene keys' defaults and --set), moves the vertices to POS.csv (header\n"
                    "x,y,z, one row per vertex) and prints the energy of each enabled term and\n"
                    "their total as one JSON object. --forces writes id,fx,fy,fz per vertex.\n"
                    "--fast evaluates with the fast kernels instead of the double reference.\n");
}

typedef struct eval_job {
    sb_cli_args args;
    sb_scene scene;
    sb_mesh mesh;
    sb_model* model;
    double* positions; /* 3n */
    double* forces;    /* 3n */
    sb_energies energies;
} eval_job;

static int eval_finish(eval_job* job, int code) {
    free(job->positions);
    free(job->forces);
    sb_model_destroy(job->model);
    sb_mesh_free(&job->mesh);
    sb_scene_free(&job->scene);
    sb_cli_args_free(&job->args);
    return code;
}

static sb_status load_positions(eval_job* job, sb_error* err) {
    size_t n = 3 * (size_t)job->mesh.vertex_count;
    job->positions = malloc((n ? n : 1) * sizeof(double));
    job->forces = calloc(n ? n : 1, sizeof(double));
    if (!job->positions || !job->forces) return sb_error_set(err, SB_ERR_NOMEM, "out of memory");
    memcpy(job->positions, job->mesh.positions, n * sizeof(double));
    if (!job->args.positions) return SB_OK;
    return sb_positions_read(job->args.positions, job->mesh.vertex_count, job->positions, err);
}

static sb_status evaluate_fast(eval_job* job, sb_error* err) {
    sb_solver_def def = sb_scene_solver_def(&job->scene);
    def.kernels = SB_KERNELS_FAST;
    memset(def.gravity, 0, sizeof def.gravity);
    sb_status status = sb_simulation_threads(job->args.threads, &job->scene, &def.runtime.threads, err);
    if (status != SB_OK) return status;
    sb_solver* solver = sb_solver_create(job->model, &def, err);
    if (!solver) return SB_ERR_INVALID;
    status = sb_solver_set_state(solver, job->positions, NULL);
    if (status == SB_OK) {
        sb_solver_get_forces(solver, job->forces);
        job->energies = sb_solver_energies(solver);
    } else {
        sb_error_set(err, status, "%s", sb_solver_error(solver));
    }
    sb_solver_destroy(solver);
    return status;
}

static sb_status write_forces(const eval_job* job, sb_error* err) {
    sb_atomic_file file;
    sb_status status = sb_atomic_open(&file, job->args.forces, err);
    if (status != SB_OK) return status;
    fprintf(file.stream, "id,fx,fy,fz\n");
    for (uint32_t v = 0; v < job->mesh.vertex_count; v++)
        fprintf(file.stream, "%u,%.17g,%.17g,%.17g\n", v, job->forces[3 * v], job->forces[3 * v + 1],
                job->forces[3 * v + 2]);
    return sb_atomic_commit(&file, err);
}

static void print_json(const eval_job* job) {
    printf("{");
    for (int t = 0; t < SB_TERM_COUNT; t++)
        if (sb_model_term_enabled(job->model, (sb_term)t))
            printf("\"%s\":%.17g,", sb_term_name((sb_term)t), job->energies.term[t]);
    printf("\"total\":%.17g}\n", sb_energies_internal(&job->energies));
}

/* Everything up to the model at the positions to evaluate: bad input. */
static sb_status prepare(eval_job* job, sb_error* err) {
    sb_status status = sb_scene_read(&job->scene, NULL, job->args.sets, (size_t)job->args.set_count, err);
    if (status != SB_OK) return status;
    status = sb_mesh_load(job->args.input, &job->mesh, err);
    if (status != SB_OK) return status;
    job->model = sb_scene_build_model(&job->scene, &job->mesh, job->args.input, err);
    if (!job->model) return SB_ERR_INVALID;
    return load_positions(job, err);
}

static int evaluate(eval_job* job, sb_error* err) {
    if (job->args.fast) {
        if (evaluate_fast(job, err) != SB_OK) return SB_EXIT_FAILURE;
    } else if (sb_reference_forces(job->model, job->positions, NULL, job->forces, &job->energies, err) != SB_OK) {
        /* a collapsed edge at the given positions */
        sb_error_prefix(err, SB_ERR_DEGENERATE, job->args.positions ? job->args.positions : job->args.input);
        return SB_EXIT_INPUT;
    }
    if (job->args.forces && write_forces(job, err) != SB_OK) return SB_EXIT_FAILURE;
    print_json(job);
    return SB_EXIT_OK;
}

int sb_cli_eval(int argc, char** argv) {
    static const char* const accepted[] = {"--positions", "--forces", "--fast", NULL};
    eval_job job = {0};
    sb_error err;
    if (sb_cli_parse(argc, argv, accepted, &job.args, &err) != SB_OK)
        return eval_finish(&job, sb_cli_fail(SB_EXIT_INPUT, &err));
    if (job.args.help) {
        sb_cli_eval_usage(stdout);
        return eval_finish(&job, SB_EXIT_OK);
    }
    if (prepare(&job, &err) != SB_OK) return eval_finish(&job, sb_cli_fail(SB_EXIT_INPUT, &err));
    int code = evaluate(&job, &err);
    if (code != SB_EXIT_OK) sb_cli_fail(code, &err);
    return eval_finish(&job, code);
}
