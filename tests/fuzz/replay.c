/* sb_fuzz_replay CORPUS [SECONDS]: feeds every file of CORPUS/<entry>/
 * to that entry of entries.c, each in a child process under an alarm of
 * SECONDS (default 10). A file passes when its child exits 0: the parser
 * accepted it or refused it with a message. A signal (a crash, the
 * alarm), a sanitizer report or a leak (the child ends with exit(), so
 * LeakSanitizer looks) fails it. Prints each failure and a summary; exits
 * 1 when any failed. `make test` runs it under the address and
 * undefined-behaviour sanitizers (ctest fuzz_replay). */
#define _POSIX_C_SOURCE 200809L
#include <dirent.h>
#include <errno.h>
#include <signal.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "tests/fuzz/entries.h"

static unsigned char* read_file(const char* path, size_t* size) {
    FILE* f = fopen(path, "rb");
    if (!f) return NULL;
    size_t capacity = 1 << 16, used = 0;
    unsigned char* data = malloc(capacity);
    for (size_t got = 1; data && got > 0; used += got) {
        if (used == capacity) {
            unsigned char* grown = realloc(data, capacity *= 2);
            if (!grown) free(data);
            data = grown;
            if (!data) break;
        }
        got = fread(data + used, 1, capacity - used, f);
    }
    fclose(f);
    *size = used;
    return data;
}

/* Runs entry on the file in a child; true when it exits 0. */
static bool replay_one(const sb_fuzz_entry* entry, const char* path, unsigned seconds) {
    fflush(NULL);
    pid_t pid = fork();
    if (pid == 0) {
        size_t size = 0;
        unsigned char* data = read_file(path, &size);
        if (!data) _exit(3);
        alarm(seconds);
        entry->run(data, size);
        free(data);
        exit(0);
    }
    int status;
    if (pid < 0 || waitpid(pid, &status, 0) != pid) {
        printf("%s: cannot run: %s\n", path, strerror(errno));
        return false;
    }
    if (WIFEXITED(status) && WEXITSTATUS(status) == 0) return true;
    if (WIFSIGNALED(status) && WTERMSIG(status) == SIGALRM)
        printf("%s: no end within %u s\n", path, seconds);
    else if (WIFSIGNALED(status))
        printf("%s: killed by signal %d (%s)\n", path, WTERMSIG(status), strsignal(WTERMSIG(status)));
    else
        printf("%s: exit code %d (a sanitizer's report is above)\n", path, WEXITSTATUS(status));
    return false;
}

static bool is_entry(const char* name) { return name[0] != '.'; }

/* The names of a folder's files (not starting with '.'), read before any
 * child starts, so that no child holds the open folder; held in a global,
 * where the children's LeakSanitizer finds them reachable. */
static struct {
    char** names;
    size_t count;
} listing;

static void list_folder(const char* dir) {
    DIR* d = opendir(dir);
    for (struct dirent* e; d && (e = readdir(d));) {
        if (!is_entry(e->d_name)) continue;
        char** grown = realloc(listing.names, (listing.count + 1) * sizeof *listing.names);
        if (!grown) break;
        listing.names = grown;
        if ((listing.names[listing.count] = strdup(e->d_name))) listing.count++;
    }
    if (d) closedir(d);
}

static void free_listing(void) {
    for (size_t i = 0; i < listing.count; i++) free(listing.names[i]);
    free(listing.names);
    listing.names = NULL;
    listing.count = 0;
}

/* Every file of dir; adds to *files and *failed. */
static void replay_folder(const sb_fuzz_entry* entry, const char* dir, unsigned seconds, int* files, int* failed) {
    list_folder(dir);
    for (size_t i = 0; i < listing.count; i++) {
        char path[4096];
        if (snprintf(path, sizeof path, "%s/%s", dir, listing.names[i]) >= (int)sizeof path) continue;
        ++*files;
        *failed += !replay_one(entry, path, seconds);
    }
    free_listing();
}

int main(int argc, char** argv) {
    if (argc < 2 || argc > 3) {
        fprintf(stderr, "usage: sb_fuzz_replay CORPUS [SECONDS]\n");
        return 2;
    }
    unsigned seconds = argc == 3 ? (unsigned)atoi(argv[2]) : 10;
    int files = 0, failed = 0, folders = 0;
    for (size_t i = 0; i < sb_fuzz_entry_count; i++) {
        char dir[4096];
        snprintf(dir, sizeof dir, "%s/%s", argv[1], sb_fuzz_entries[i].name);
        int before = files;
        replay_folder(&sb_fuzz_entries[i], dir, seconds, &files, &failed);
        folders += files > before;
    }
    printf("sb_fuzz_replay: %d files of %d entries, %d failed\n", files, folders, failed);
    return failed || files == 0 ? 1 : 0;
}
