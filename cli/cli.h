/* The `softbond` program's commands and what they share: argument parsing,
 * the scene from file and --set, exit codes. Every error is one line on
 * stderr, "softbond: WHERE: message". */
#ifndef SB_CLI_H
#define SB_CLI_H

#include <stdio.h>

#include "scenes/simulation.h"

enum {
    SB_EXIT_OK = 0,
    SB_EXIT_FAILURE = 1, /* an output file could not be written */
    SB_EXIT_INPUT = 2,   /* bad input: arguments, scene, mesh, CSV */
    SB_EXIT_SOLVER = 3   /* the solver failed during the run */
};

/* The options of every command; a command says which it accepts. */
typedef struct sb_cli_args {
    const char* input; /* the one positional argument */
    const char** sets; /* each --set key=value, in order */
    int set_count;
    const char* output;           /* run --output DIR */
    const char* threads;          /* run --threads N */
    const char* positions;        /* eval --positions POS.csv */
    const char* forces;           /* eval --forces OUT.csv */
    bool fast;                    /* eval --fast */
    const char* budget_ms;        /* run --budget-ms X */
    const char* max_error;        /* run --max-error M (with --budget-ms) */
    bool no_realtime;             /* run --no-realtime */
    const char* checkpoint_every; /* run --checkpoint-every T */
    const char* resume;           /* run --resume DIR, sweep --resume DIR */
    const char* end_positions;    /* run --end-positions FILE.csv */
    const char* workers;          /* sweep --workers N */
    const char* screenshot;       /* view --screenshot FILE.png */
    const char* frames;           /* view --frames N */
    const char* script;           /* view --script FILE */
    const char* size;             /* view, film --size WxH */
    const char* movie;            /* film --movie OUT.mp4 */
    const char* fps;              /* film --fps F */
    const char* render_share;     /* view --render-share X */
    const char* eye;              /* film --eye x,y,z */
    const char* target;           /* film --target x,y,z */
    bool help;                    /* --help, -h */
} sb_cli_args;

/* Parses argv[1..] (argv[0] is the command's name). `accepted` lists the
 * options the command takes ("--output", ...; --set and --help always).
 * Fails on an unknown option, a missing value or a missing or extra
 * positional argument (unless --help). */
sb_status sb_cli_parse(int argc, char** argv, const char* const* accepted, sb_cli_args* out, sb_error* err);
void sb_cli_args_free(sb_cli_args* args);

/* The arguments a simulation is made from (scenes/simulation.h). */
sb_simulation_args sb_cli_simulation_args(const sb_cli_args* args);

/* Refuses haptics.device: mouse (its place named) in a command other than
 * view: nothing moves that device there, so the tool would stand still. */
sb_status sb_cli_no_mouse(const sb_scene* scene, const char* command, sb_error* err);

/* --size "WxH", each 16 to 8192 pixels. */
sb_status sb_cli_size(const char* text, int* width, int* height, sb_error* err);

/* Prints "softbond: message" on stderr, one line (control bytes and bytes
 * that are not UTF-8 escaped: \n, \x1b), and returns code. */
int sb_cli_fail(int code, const sb_error* err);

int sb_cli_run(int argc, char** argv);
int sb_cli_eval(int argc, char** argv);
int sb_cli_info(int argc, char** argv);
/* `softbond view` and `softbond film` (view_cli.c, film.c): the real-time viewer and the film maker. */
int sb_cli_view(int argc, char** argv);
int sb_cli_film(int argc, char** argv);
void sb_cli_view_usage(FILE* stream);
void sb_cli_film_usage(FILE* stream);
/* `softbond tetra IN OUT` (tetra.c): its own arguments, two positional. */
int sb_cli_tetra(int argc, char** argv);
void sb_cli_run_usage(FILE* stream);
void sb_cli_eval_usage(FILE* stream);
void sb_cli_info_usage(FILE* stream);
void sb_cli_tetra_usage(FILE* stream);
/* `softbond keys` (keys.c): the scene keys' reference, from the parser's table. */
int sb_cli_keys(int argc, char** argv);
void sb_cli_keys_usage(FILE* stream);
/* `softbond sweep SWEEP.yaml` (sweep.c) and `softbond fit FIT.yaml` (fit.c): studies of many runs. */
int sb_cli_sweep(int argc, char** argv);
void sb_cli_sweep_usage(FILE* stream);
int sb_cli_fit(int argc, char** argv);
void sb_cli_fit_usage(FILE* stream);

#endif
