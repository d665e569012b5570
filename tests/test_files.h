/* Shared by the tests that write files or run the `softbond` program: a
 * temporary directory, files in it, and a child process's exit code,
 * stdout and stderr. Include after test_util.h, with _POSIX_C_SOURCE
 * 200809L defined before any system header. */
#ifndef SB_TEST_FILES_H
#define SB_TEST_FILES_H

#include <stdio.h>
#include <sys/wait.h>
#include <unistd.h>

#include "tests/test_util.h"

static char tu_tmp_dir[256];

/* Makes TMPDIR/PREFIX_XXXXXX (or /tmp/...); 0 on success, for cmocka setups. */
static inline int tu_make_tmp_dir(const char* prefix) {
    const char* base = getenv("TMPDIR");
    snprintf(tu_tmp_dir, sizeof tu_tmp_dir, "%s/%s_XXXXXX", base && *base ? base : "/tmp", prefix);
    return mkdtemp(tu_tmp_dir) ? 0 : -1;
}

/* Removes the directory and all the tests made in it. */
static inline int tu_remove_tmp_dir(void) {
    char command[400];
    snprintf(command, sizeof command, "rm -rf '%s'", tu_tmp_dir);
    return system(command) == 0 ? 0 : -1;
}

/* tu_tmp_dir/name in a rotating set of buffers, enough for one call's paths. */
static inline const char* tu_tmp_path(const char* name) {
    static char buffers[8][1024];
    static int next;
    char* path = buffers[next++ % 8];
    snprintf(path, sizeof buffers[0], "%s/%s", tu_tmp_dir, name);
    return path;
}

/* Writes text to tu_tmp_dir/name and returns that path. */
static inline const char* tu_write_file(const char* name, const char* text) {
    const char* path = tu_tmp_path(name);
    FILE* f = fopen(path, "w");
    assert_non_null(f);
    fputs(text, f);
    fclose(f);
    return path;
}

/* The whole file, or NULL when it does not exist. Caller frees. */
static inline char* tu_read_file(const char* path) {
    FILE* f = fopen(path, "rb");
    if (!f) return NULL;
    fseek(f, 0, SEEK_END);
    long size = ftell(f);
    fseek(f, 0, SEEK_SET);
    char* text = malloc((size_t)size + 1);
    assert_non_null(text);
    assert_int_equal(fread(text, 1, (size_t)size, f), (size_t)size);
    text[size] = '\0';
    fclose(f);
    return text;
}

/* What a run of the program left: exit code, stdout, stderr. */
typedef struct tu_result {
    int code;
    char* out;
    char* err;
} tu_result;

static inline void tu_result_free(tu_result* r) {
    free(r->out);
    free(r->err);
}

/* Runs softbond with args (NULL-terminated) in tu_tmp_dir, with the
 * variable env_name (unless NULL) set to env_value in its environment. */
static inline tu_result tu_run_env(const char* env_name, const char* env_value, const char* const* args) {
    const char* argv[32] = {SB_PROGRAM};
    int argc = 1;
    for (; args[argc - 1]; argc++) argv[argc] = args[argc - 1];
    argv[argc] = NULL;
    pid_t pid = fork();
    assert_true(pid >= 0);
    if (pid == 0) {
        bool ok = chdir(tu_tmp_dir) == 0 && freopen("stdout.txt", "w", stdout) && freopen("stderr.txt", "w", stderr);
        if (ok && env_name) ok = setenv(env_name, env_value, 1) == 0;
        if (ok) execv(SB_PROGRAM, (char* const*)argv);
        _exit(127);
    }
    int status;
    assert_int_equal(waitpid(pid, &status, 0), pid);
    assert_true(WIFEXITED(status));
    tu_result r = {WEXITSTATUS(status), tu_read_file(tu_tmp_path("stdout.txt")),
                   tu_read_file(tu_tmp_path("stderr.txt"))};
    assert_int_not_equal(r.code, 127);
    assert_non_null(r.out);
    assert_non_null(r.err);
    return r;
}

static inline tu_result tu_run(const char* const* args) { return tu_run_env(NULL, NULL, args); }

/* `softbond run` of a scene file holding TEXT exits 2 with MESSAGE in its
 * error line. */
static inline void tu_assert_scene_fails(const char* text, const char* message) {
    tu_write_file("bad.yaml", text);
    tu_result r = tu_run((const char*[]){"run", "bad.yaml", "--output", "never", NULL});
    if (r.code != 2 || !strstr(r.err, message))
        fail_msg("expected exit 2 and '%s', got %d: %s", message, r.code, r.err);
    tu_result_free(&r);
}

#endif
