/* Isolated calls (see isolate.h).
 *
 * The parent forks; the child sets its limits, runs the function and
 * writes its answer into a pipe as an 8-byte length then the bytes, and
 * leaves with _exit(0) (no atexit handlers, no flushing of the parent's
 * stdio buffers). The parent reads the pipe until the answer is whole,
 * waiting with poll() no longer than the time limit, then reaps the child.
 *
 * The child's crash signals are reset to their defaults first, so that the
 * caller's handlers do not run in it, and its standard output and error go
 * to /dev/null (assimp prints its failed assertions there; the caller's
 * messages stay one line). The sanitizers' reports of the child go there
 * too: the child's end is what the caller learns.
 *
 * Limits: RLIMIT_AS is the child's address space at the fork plus
 * memory_bytes (an absolute bound would be wrong under the address
 * sanitizer, whose shadow memory is terabytes of reserved address space),
 * so an allocation storm fails inside the child (assimp then reports
 * std::bad_alloc, or the child aborts); RLIMIT_CPU backs up the
 * wall-clock limit; RLIMIT_CORE is 0, so a crash leaves no core file.
 *
 * Only the forking thread exists in the child: the function must not wait
 * for a lock another thread of the parent may hold (glibc makes malloc
 * safe across fork). An answer goes through a pipe at a few GB/s. */
#define _GNU_SOURCE
#include "mesh/io/isolate.h"
#include "common/clock.h"

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <poll.h>
#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

/* ---- the child --------------------------------------------------------------- */

/* The address space in use now, from /proc/self/statm (0 when unknown). */
static size_t address_space_now(void) {
    FILE* f = fopen("/proc/self/statm", "r");
    unsigned long pages = 0;
    if (f) {
        if (fscanf(f, "%lu", &pages) != 1) pages = 0;
        fclose(f);
    }
    return (size_t)pages * (size_t)sysconf(_SC_PAGESIZE);
}

static void set_limit(int resource, rlim_t value) {
    struct rlimit limit = {value, value};
    struct rlimit now;
    if (getrlimit(resource, &now) == 0 && now.rlim_max != RLIM_INFINITY && now.rlim_max < value) return;
    setrlimit(resource, &limit);
}

static bool write_all(int fd, const void* data, size_t size) {
    const unsigned char* p = data;
    while (size > 0) {
        ssize_t n = write(fd, p, size);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return false;
        p += n;
        size -= (size_t)n;
    }
    return true;
}

/* The caller's handlers (a test framework's, a sanitizer's) must not
 * catch the child's crash and carry on as the caller. */
static void default_crash_signals(void) {
    static const int signals[] = {SIGSEGV, SIGBUS, SIGILL, SIGFPE, SIGABRT, SIGPIPE, SIGXCPU};
    for (size_t i = 0; i < sizeof signals / sizeof signals[0]; i++) signal(signals[i], SIG_DFL);
}

/* What the child prints (assimp's "ai_assert failure in ...") would
 * break the caller's one-line messages: its output goes nowhere. */
static void silence_output(void) {
    int null = open("/dev/null", O_WRONLY);
    if (null < 0) return;
    dup2(null, STDOUT_FILENO);
    dup2(null, STDERR_FILENO);
    close(null);
}

static _Noreturn void child_main(int fd, sb_isolated_fn fn, void* arg, const sb_isolate_limits* limits) {
    default_crash_signals();
    silence_output();
    set_limit(RLIMIT_CORE, 0);
    set_limit(RLIMIT_CPU, (rlim_t)ceil(limits->seconds) + 1);
    size_t base = address_space_now();
    if (base > 0) set_limit(RLIMIT_AS, (rlim_t)(base + limits->memory_bytes));
    sb_blob answer = {0};
    fn(arg, &answer);
    uint64_t size = answer.size;
    bool sent = write_all(fd, &size, sizeof size) && write_all(fd, answer.data, answer.size);
    _exit(sent ? 0 : 1);
}

/* ---- the parent -------------------------------------------------------------- */

typedef struct reading {
    int fd;
    double deadline;
    unsigned char header[8];
    size_t got; /* bytes of header and then data received */
    uint64_t size;
    sb_blob* answer;
} reading;

/* Reads what is there into the header, then the answer. -1: error or
 * end of file; 0: more to come; 1: the answer is whole. */
static int read_some(reading* r) {
    bool in_header = r->got < sizeof r->header;
    unsigned char* into = in_header ? r->header + r->got : r->answer->data + (r->got - sizeof r->header);
    size_t want = in_header ? sizeof r->header - r->got : (size_t)(r->size - (r->got - sizeof r->header));
    ssize_t n = want ? read(r->fd, into, want) : 0;
    if (n < 0 && errno == EINTR) return 0;
    if (want && n <= 0) return -1;
    r->got += (size_t)n;
    if (in_header && r->got == sizeof r->header) {
        memcpy(&r->size, r->header, sizeof r->size);
        if (r->size > SIZE_MAX - 1 || !(r->answer->data = malloc((size_t)r->size + 1))) return -1;
        r->answer->size = (size_t)r->size;
    }
    return r->got == sizeof r->header + r->size && r->got >= sizeof r->header ? 1 : 0;
}

/* 1: whole answer; 0: timed out; -1: the pipe ended early. */
static int read_answer(reading* r) {
    for (;;) {
        double left = r->deadline - sb_wall_seconds();
        if (left <= 0.0) return 0;
        struct pollfd p = {r->fd, POLLIN, 0};
        int ready = poll(&p, 1, (int)ceil(left * 1000.0));
        if (ready < 0 && errno != EINTR) return -1;
        if (ready <= 0) continue;
        int state = read_some(r);
        if (state != 0) return state;
    }
}

static void describe_end(int status, int state, const sb_isolate_limits* limits, char* why, size_t size) {
    if (state == 0)
        snprintf(why, size, "no answer within %g s", limits->seconds);
    else if (WIFSIGNALED(status) && WTERMSIG(status) == SIGXCPU)
        snprintf(why, size, "more than %g s of processor time", ceil(limits->seconds) + 1);
    else if (WIFSIGNALED(status))
        snprintf(why, size, "killed by signal %d, %s", WTERMSIG(status), strsignal(WTERMSIG(status)));
    else if (WIFEXITED(status))
        snprintf(why, size, "it exited with code %d without an answer", WEXITSTATUS(status));
    else
        snprintf(why, size, "it ended without an answer");
}

sb_status sb_isolate_run(sb_isolated_fn fn, void* arg, const sb_isolate_limits* limits, sb_blob* answer, char* why,
                         size_t why_size) {
    *answer = (sb_blob){0};
    int fds[2];
    if (pipe2(fds, O_CLOEXEC) != 0) {
        snprintf(why, why_size, "cannot make a pipe: %s", strerror(errno));
        return SB_ERR_IO;
    }
    fflush(NULL); /* nothing buffered is written twice */
    pid_t pid = fork();
    if (pid == 0) {
        close(fds[0]);
        child_main(fds[1], fn, arg, limits);
    }
    close(fds[1]);
    if (pid < 0) {
        snprintf(why, why_size, "cannot start a process: %s", strerror(errno));
        close(fds[0]);
        return SB_ERR_IO;
    }
    reading r = {.fd = fds[0], .deadline = sb_wall_seconds() + limits->seconds, .answer = answer};
    int state = read_answer(&r);
    close(fds[0]);
    if (state != 1) kill(pid, SIGKILL);
    int status = 0;
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    if (state == 1 && WIFEXITED(status) && WEXITSTATUS(status) == 0) return SB_OK;
    describe_end(status, state, limits, why, why_size);
    free(answer->data);
    *answer = (sb_blob){0};
    return SB_ERR_IO;
}
