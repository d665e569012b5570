/* run.yaml (see run_record.h). */
#define _POSIX_C_SOURCE 200809L
#include "cli/run_record.h"
#include "common/atomic_file.h"

#include <string.h>

#ifndef SB_GIT_COMMIT
#define SB_GIT_COMMIT "unknown"
#endif

/* An argument as a POSIX shell reads it back: bare when safe, else in single quotes. */
static void put_shell_word(FILE* f, const char* word) {
    bool bare = word[0] != '\0';
    for (const char* p = word; *p && bare; p++)
        bare = strchr("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_-./=,:@+%", *p) != NULL;
    if (bare) {
        fputs(word, f);
        return;
    }
    fputc('\'', f);
    for (const char* p = word; *p; p++) {
        if (*p == '\'')
            fputs("'\\''", f);
        else if (*p == '\n')
            fputc(' ', f); /* a comment stays one line */
        else
            fputc(*p, f);
    }
    fputc('\'', f);
}

sb_status sb_run_record_write(const char* path, const sb_run_record* record, sb_error* err) {
    sb_atomic_file file;
    sb_status status = sb_atomic_open(&file, path, err);
    if (status != SB_OK) return status;
    FILE* f = file.stream;
    char machine[256];
    sb_runtime_describe(machine, sizeof machine);
    fprintf(f,
            "# The scene as this run used it: every key, after --set, defaults included.\n"
            "# `softbond run run.yaml --output DIR` runs it again, bitwise the same.\n"
            "# softbond %s, commit %s\n"
            "# precision: %s; SIMD: %s; kernels: %s; threads: %d\n"
            "# machine: %s\n"
            "# command: softbond",
            SB_VERSION_STRING, SB_GIT_COMMIT, sizeof(sb_real) == sizeof(double) ? "double" : "float",
            sb_runtime_simd(), sb_scene_string(record->scene, SB_KEY_KERNELS), record->threads, machine);
    for (int i = 0; i < record->argc; i++) {
        fputc(' ', f);
        put_shell_word(f, record->argv[i]);
    }
    fputs("\n\n", f);
    sb_scene_write(record->scene, f);
    return sb_atomic_commit(&file, err);
}
