/* What the commands share (see cli.h). */
#define _POSIX_C_SOURCE 200809L
#include "cli/cli.h"
#include "common/error.h"
#include "scenes/suggest.h"

#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct option_spec {
    const char* name;
    size_t offset; /* of a const char* value, or of the bool for a flag */
    bool flag;
} option_spec;

static const option_spec option_specs[] = {
    {"--output", offsetof(sb_cli_args, output), false},
    {"--threads", offsetof(sb_cli_args, threads), false},
    {"--positions", offsetof(sb_cli_args, positions), false},
    {"--forces", offsetof(sb_cli_args, forces), false},
    {"--fast", offsetof(sb_cli_args, fast), true},
    {"--budget-ms", offsetof(sb_cli_args, budget_ms), false},
    {"--max-error", offsetof(sb_cli_args, max_error), false},
    {"--no-realtime", offsetof(sb_cli_args, no_realtime), true},
    {"--checkpoint-every", offsetof(sb_cli_args, checkpoint_every), false},
    {"--resume", offsetof(sb_cli_args, resume), false},
    {"--end-positions", offsetof(sb_cli_args, end_positions), false},
    {"--workers", offsetof(sb_cli_args, workers), false},
    {"--screenshot", offsetof(sb_cli_args, screenshot), false},
    {"--frames", offsetof(sb_cli_args, frames), false},
    {"--script", offsetof(sb_cli_args, script), false},
    {"--size", offsetof(sb_cli_args, size), false},
    {"--movie", offsetof(sb_cli_args, movie), false},
    {"--fps", offsetof(sb_cli_args, fps), false},
    {"--render-share", offsetof(sb_cli_args, render_share), false},
    {"--eye", offsetof(sb_cli_args, eye), false},
    {"--target", offsetof(sb_cli_args, target), false},
};

static bool accepts(const char* const* accepted, const char* name) {
    for (; *accepted; accepted++)
        if (strcmp(*accepted, name) == 0) return true;
    return false;
}

/* "--name=value" or "--name value"; returns the value or NULL. */
static const char* option_value(int argc, char** argv, int* i, size_t name_length) {
    if (argv[*i][name_length] == '=') return argv[*i] + name_length + 1;
    return *i + 1 < argc ? argv[++*i] : NULL;
}

static const option_spec* find_option(const char* arg, const char* const* accepted) {
    for (size_t s = 0; s < sizeof option_specs / sizeof option_specs[0]; s++) {
        size_t n = strlen(option_specs[s].name);
        bool match =
            strncmp(arg, option_specs[s].name, n) == 0 && (arg[n] == '\0' || (arg[n] == '=' && !option_specs[s].flag));
        if (match && accepts(accepted, option_specs[s].name)) return &option_specs[s];
    }
    return NULL;
}

static sb_status usage_fail(sb_error* err, const char* command, const char* format, const char* what) {
    char message[sizeof err->message];
    snprintf(message, sizeof message, format, what);
    return sb_error_set(err, SB_ERR_INVALID, "%s (see softbond %s --help)", message, command);
}

/* "unknown option '--thread' (did you mean '--threads'?)": the nearest of
 * the command's options (and --set, --help). */
static sb_status unknown_option(sb_error* err, const char* command, const char* arg, const char* const* accepted) {
    const char* names[64];
    size_t count = 0;
    for (; *accepted && count < 62; accepted++) names[count++] = *accepted;
    names[count++] = "--set";
    names[count++] = "--help";
    char word[128];
    snprintf(word, sizeof word, "%.*s", (int)strcspn(arg, "="), arg);
    const char* near = sb_suggest(word, names, count);
    char message[sizeof err->message];
    snprintf(message, sizeof message, "unknown option '%s'%s%s%s", arg, near ? " (did you mean '" : "",
             near ? near : "", near ? "'?)" : "");
    return sb_error_set(err, SB_ERR_INVALID, "%s (see softbond %s --help)", message, command);
}

static sb_status parse_option(int argc, char** argv, int* i, const char* const* accepted, sb_cli_args* out,
                              sb_error* err) {
    const char* arg = argv[*i];
    bool is_set = strncmp(arg, "--set", 5) == 0 && (arg[5] == '\0' || arg[5] == '=');
    const option_spec* spec = is_set ? NULL : find_option(arg, accepted);
    if (!is_set && !spec) return unknown_option(err, argv[0], arg, accepted);
    if (spec && spec->flag) {
        *(bool*)((char*)out + spec->offset) = true;
        return SB_OK;
    }
    const char* value = option_value(argc, argv, i, is_set ? 5 : strlen(spec->name));
    if (!value) return usage_fail(err, argv[0], "%s needs a value", arg);
    if (is_set)
        out->sets[out->set_count++] = value;
    else
        *(const char**)((char*)out + spec->offset) = value;
    return SB_OK;
}

static sb_status parse_arg(int argc, char** argv, int* i, const char* const* accepted, sb_cli_args* out,
                           sb_error* err) {
    const char* arg = argv[*i];
    if (strcmp(arg, "--help") == 0 || strcmp(arg, "-h") == 0) {
        out->help = true;
        return SB_OK;
    }
    if (arg[0] == '-' && arg[1] != '\0') return parse_option(argc, argv, i, accepted, out, err);
    if (out->input) return usage_fail(err, argv[0], "unexpected argument '%s'", arg);
    out->input = arg;
    return SB_OK;
}

/* What the command's one positional argument is, for "missing ...". */
static const char* missing_input(const char* command) {
    if (strcmp(command, "eval") == 0 || strcmp(command, "info") == 0) return "MESH";
    if (strcmp(command, "sweep") == 0) return "SWEEP.yaml";
    return strcmp(command, "fit") == 0 ? "FIT.yaml" : "SCENE";
}

sb_status sb_cli_parse(int argc, char** argv, const char* const* accepted, sb_cli_args* out, sb_error* err) {
    *out = (sb_cli_args){.sets = malloc((size_t)argc * sizeof *out->sets)};
    if (!out->sets) return sb_error_set(err, SB_ERR_NOMEM, "out of memory");
    for (int i = 1; i < argc; i++) {
        sb_status status = parse_arg(argc, argv, &i, accepted, out, err);
        if (status != SB_OK) return status;
    }
    if (!out->input && !out->help) return usage_fail(err, argv[0], "missing %s", missing_input(argv[0]));
    return SB_OK;
}

/* A whole number in [lo, hi] from text, or false. */
static bool whole(const char* text, long lo, long hi, long* out) {
    char* end;
    *out = strtol(text, &end, 10);
    return end != text && *end == '\0' && *out >= lo && *out <= hi;
}

sb_status sb_cli_size(const char* text, int* width, int* height, sb_error* err) {
    long w, h;
    char copy[64];
    snprintf(copy, sizeof copy, "%s", text);
    char* x = strchr(copy, 'x');
    if (x) *x = '\0';
    if (!x || !whole(copy, 16, 8192, &w) || !whole(x + 1, 16, 8192, &h))
        return sb_error_set(err, SB_ERR_INVALID, "--size: expected WxH (16 to 8192 pixels each), got '%s'", text);
    *width = (int)w, *height = (int)h;
    return SB_OK;
}

sb_simulation_args sb_cli_simulation_args(const sb_cli_args* args) {
    return (sb_simulation_args){.input = args->input,
                                .sets = args->sets,
                                .set_count = args->set_count,
                                .threads = args->threads,
                                .budget_ms = args->budget_ms,
                                .max_error = args->max_error};
}

sb_status sb_cli_no_mouse(const sb_scene* scene, const char* command, sb_error* err) {
    if (strcmp(sb_scene_string(scene, SB_KEY_HAPTICS_DEVICE), "mouse") != 0) return SB_OK;
    return sb_scene_fail(scene, SB_KEY_HAPTICS_DEVICE, err,
                         "'haptics.device: mouse' is moved by the mouse in softbond view only: in softbond %s the "
                         "tool would stand still (use scripted or udp here)",
                         command);
}

void sb_cli_args_free(sb_cli_args* args) {
    free(args->sets);
    args->sets = NULL;
}

/* The length of the valid UTF-8 sequence at s (2 to 4 bytes), or 0. */
static int utf8_length(const unsigned char* s) {
    int n = s[0] >= 0xf0 && s[0] <= 0xf4 ? 4 : s[0] >= 0xe0 ? 3 : s[0] >= 0xc2 && s[0] < 0xe0 ? 2 : 0;
    for (int i = 1; i < n; i++)
        if ((s[i] & 0xc0) != 0x80) return 0;
    return n;
}

/* text with control bytes and bytes that are not UTF-8 written as \n, \r,
 * \t or \xHH: a message quotes bytes of files, and stays one line. */
static void put_escaped(FILE* stream, const char* text) {
    for (const unsigned char* p = (const unsigned char*)text; *p;) {
        int n = *p >= 0x80 ? utf8_length(p) : 1;
        if (n > 1) {
            fwrite(p, 1, (size_t)n, stream);
            p += n;
            continue;
        }
        if (*p == '\n' || *p == '\r' || *p == '\t')
            fprintf(stream, "\\%c", *p == '\n' ? 'n' : *p == '\r' ? 'r' : 't');
        else if (*p < 0x20 || *p == 0x7f || *p >= 0x80)
            fprintf(stream, "\\x%02x", *p);
        else
            fputc(*p, stream);
        p++;
    }
}

int sb_cli_fail(int code, const sb_error* err) {
    fputs("softbond: ", stderr);
    put_escaped(stderr, err->message);
    fputc('\n', stderr);
    return code;
}
