/* One run of a study (see study_case.h). */
#define _POSIX_C_SOURCE 200809L
#define _XOPEN_SOURCE 700
#include "cli/study_case.h"
#include "cli/output_dir.h"
#include "common/error.h"

#include <errno.h>
#include <fcntl.h>
#include <ftw.h>
#include <signal.h>
#include <spawn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

extern char** environ;

enum { FIXED_ARGS = 12 };

/* softbond run SCENE --set ... --output DIR --end-positions DIR/end_positions.csv [--threads N] */
static char** make_argv(const sb_study_run* run, char* positions) {
    char** argv = calloc(2 * run->set_count + FIXED_ARGS, sizeof *argv);
    if (!argv) return NULL;
    size_t n = 0;
    argv[n++] = "softbond";
    argv[n++] = "run";
    argv[n++] = (char*)run->scene;
    for (size_t i = 0; i < run->set_count; i++) {
        argv[n++] = "--set";
        argv[n++] = (char*)run->sets[i];
    }
    argv[n++] = "--output";
    argv[n++] = (char*)run->dir;
    argv[n++] = "--end-positions";
    argv[n++] = positions;
    if (run->threads) {
        argv[n++] = "--threads";
        argv[n++] = (char*)run->threads;
    }
    return argv;
}

/* This process's environment with SB_STUDY_PARENT_ENV=<this pid> in place
 * of any it had; its strings are environ's but the last, `own`. NULL when
 * out of memory. */
static char** make_envp(char* own, size_t size) {
    size_t n = 0, prefix = strlen(SB_STUDY_PARENT_ENV "=");
    while (environ[n]) n++;
    char** envp = calloc(n + 2, sizeof *envp);
    if (!envp) return NULL;
    size_t k = 0;
    for (size_t i = 0; i < n; i++)
        if (strncmp(environ[i], SB_STUDY_PARENT_ENV "=", prefix) != 0) envp[k++] = environ[i];
    snprintf(own, size, SB_STUDY_PARENT_ENV "=%ld", (long)getpid());
    envp[k] = own;
    return envp;
}

static sb_status spawn_in(const sb_study_run* run, sb_output_dir* out, pid_t* pid, sb_error* err) {
    char stdout_path[sizeof out->path], positions[sizeof out->path];
    snprintf(stdout_path, sizeof stdout_path, "%s", sb_output_dir_path(out, "stdout.txt"));
    snprintf(positions, sizeof positions, "%s", sb_output_dir_path(out, "end_positions.csv"));
    unlink(positions); /* a resumed case's old one */
    char** argv = make_argv(run, positions);
    char own[64];
    char** envp = make_envp(own, sizeof own);
    if (!argv || !envp) {
        free(argv);
        free(envp);
        return sb_error_set(err, SB_ERR_NOMEM, "out of memory");
    }
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 1, stdout_path, O_WRONLY | O_CREAT | O_TRUNC, 0666);
    posix_spawn_file_actions_addopen(&actions, 2, sb_output_dir_path(out, "stderr.txt"), O_WRONLY | O_CREAT | O_TRUNC,
                                     0666);
    int code = posix_spawn(pid, "/proc/self/exe", &actions, NULL, argv, envp);
    posix_spawn_file_actions_destroy(&actions);
    free(argv);
    free(envp);
    return code == 0 ? SB_OK : sb_error_set(err, SB_ERR_IO, "cannot start softbond run: %s", strerror(code));
}

sb_status sb_study_spawn(const sb_study_run* run, pid_t* pid, sb_error* err) {
    sb_output_dir out = {0};
    sb_status status = sb_output_dir_create(&out, run->dir, "", err);
    if (status == SB_OK) status = spawn_in(run, &out, pid, err);
    sb_output_dir_free(&out);
    return status;
}

/* The last line of the file that is not blank, without a "softbond: " prefix. */
static void last_line(const char* path, char* out, size_t size) {
    out[0] = '\0';
    FILE* f = fopen(path, "r");
    if (!f) return;
    char line[1024];
    while (fgets(line, sizeof line, f)) {
        line[strcspn(line, "\r\n")] = '\0';
        if (line[0] == '\0') continue;
        const char* text = strncmp(line, "softbond: ", 10) == 0 ? line + 10 : line;
        size_t n = strlen(text) < size ? strlen(text) : size - 1;
        memcpy(out, text, n);
        out[n] = '\0';
    }
    fclose(f);
}

void sb_study_outcome_read(int wait_status, const char* dir, sb_study_outcome* out) {
    *out = (sb_study_outcome){0};
    if (WIFSIGNALED(wait_status)) {
        int signal = WTERMSIG(wait_status);
        out->status = 128 + signal;
        snprintf(out->message, sizeof out->message, "killed by signal %d (%s)", signal, strsignal(signal));
        return;
    }
    out->status = WEXITSTATUS(wait_status);
    if (out->status == 0) return;
    char path[4096];
    snprintf(path, sizeof path, "%s/stderr.txt", dir);
    last_line(path, out->message, sizeof out->message);
}

sb_status sb_study_run_wait(const sb_study_run* run, sb_study_outcome* out, sb_error* err) {
    pid_t pid;
    sb_status status = sb_study_spawn(run, &pid, err);
    if (status != SB_OK) return status;
    int wait_status;
    while (waitpid(pid, &wait_status, 0) < 0)
        if (errno != EINTR) return sb_error_set(err, SB_ERR_IO, "waitpid: %s", strerror(errno));
    sb_study_outcome_read(wait_status, run->dir, out);
    return SB_OK;
}

void sb_study_end_with_parent(void) {
    const char* study = getenv(SB_STUDY_PARENT_ENV);
    if (!study) return;
    prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (getppid() != (pid_t)strtol(study, NULL, 10)) _exit(128 + SIGKILL); /* it ended before the request */
}

static int remove_entry(const char* path, const struct stat* info, int type, struct FTW* where) {
    (void)info, (void)type, (void)where;
    remove(path);
    return 0;
}

void sb_study_remove_dir(const char* dir) { nftw(dir, remove_entry, 16, FTW_DEPTH | FTW_PHYS); }
