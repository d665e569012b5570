/* The run's checkpoints (see checkpoint.h). */
#define _GNU_SOURCE
#include "cli/checkpoint.h"
#include "common/atomic_file.h"
#include "common/error.h"
#include "common/sections.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#define SB_CHECKPOINT_MAGIC "SBCHKPNT"
#define SB_CHECKPOINT_VERSION 1

static const char sb_run_tag[4] = {'R', 'U', 'N', ' '}, sb_times_tag[4] = {'T', 'I', 'M', 'E'},
                  sb_solver_tag[4] = {'S', 'O', 'L', 'V'}, sb_files_tag[4] = {'F', 'I', 'L', 'E'};

/* A whole regular file (caller frees). */
static sb_status read_bytes(const char* path, uint8_t** data, size_t* size, sb_error* err) {
    FILE* file = fopen(path, "rb");
    if (!file) return sb_error_set(err, SB_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
    struct stat info;
    sb_status status = SB_OK;
    if (fstat(fileno(file), &info) != 0 || !S_ISREG(info.st_mode))
        status = sb_error_set(err, SB_ERR_IO, "%s: not a regular file", path);
    else if (!(*data = malloc((size_t)info.st_size + 1)))
        status = sb_error_set(err, SB_ERR_NOMEM, "%s: out of memory", path);
    else if ((*size = fread(*data, 1, (size_t)info.st_size, file)) != (size_t)info.st_size || ferror(file))
        status = sb_error_set(err, SB_ERR_IO, "%s: cannot read: %s", path, strerror(errno ? errno : EIO));
    fclose(file);
    return status;
}

void sb_checkpoint_files_free(sb_checkpoint_files* files) {
    for (uint32_t i = 0; i < files->count; i++) free(files->paths[i]);
    files->count = 0;
}

/* The hash of a whole file's bytes. */
static sb_status hash_file(const char* path, uint64_t* hash, sb_error* err) {
    uint8_t* data = NULL;
    size_t size = 0;
    sb_status status = read_bytes(path, &data, &size, err);
    if (status == SB_OK) *hash = sb_hash(SB_HASH_START, data, size);
    free(data);
    return status;
}

static sb_status add_file(sb_checkpoint_files* files, const char* path, size_t length, sb_error* err) {
    for (uint32_t i = 0; i < files->count; i++)
        if (strlen(files->paths[i]) == length && strncmp(files->paths[i], path, length) == 0) return SB_OK;
    if (files->count == SB_CHECKPOINT_FILES_MAX)
        return sb_error_set(err, SB_ERR_INVALID, "checkpoints: the scene reads more than %d files",
                            SB_CHECKPOINT_FILES_MAX);
    char* copy = strndup(path, length);
    if (!copy) return sb_error_set(err, SB_ERR_NOMEM, "out of memory");
    files->paths[files->count] = copy;
    sb_status status = hash_file(copy, &files->hashes[files->count], err);
    files->count++;
    return status;
}

static bool ends_with(const char* text, size_t length, const char* tail) {
    size_t n = strlen(tail);
    return length >= n && strncmp(text + length - n, tail, n) == 0;
}

/* Every `file: '...'` value of the resolved scene (sb_scene_write gives
 * them absolute, quoted, a quote doubled), and a TetGen mesh's other file. */
static sb_status scene_files(const char* text, sb_checkpoint_files* files, sb_error* err) {
    for (const char* line = text; *line; line += strcspn(line, "\n") + (line[strcspn(line, "\n")] == '\n')) {
        const char* at = line + strspn(line, " -");
        if (strncmp(at, "file: '", 7) != 0) continue;
        at += 7;
        char path[4096];
        size_t n = 0;
        for (; *at && *at != '\n' && n + 1 < sizeof path; at++) {
            if (*at == '\'' && at[1] != '\'') break;
            if (*at == '\'') at++;
            path[n++] = *at;
        }
        if (n == 0) continue;
        path[n] = '\0';
        sb_status status = add_file(files, path, n, err);
        if (status == SB_OK && (ends_with(path, n, ".node") || ends_with(path, n, ".ele"))) {
            bool node = ends_with(path, n, ".node");
            size_t stem = n - (node ? 5 : 4);
            if (stem + 6 < sizeof path) {
                strcpy(path + stem, node ? ".ele" : ".node");
                status = add_file(files, path, strlen(path), err);
            }
        }
        if (status != SB_OK) return status;
    }
    return SB_OK;
}

sb_status sb_checkpoint_scene_hash(const sb_scene* scene, const sb_cli_args* args, uint64_t* hash,
                                   sb_checkpoint_files* files, sb_error* err) {
    (void)args;
    char* text = NULL;
    size_t size = 0;
    FILE* stream = open_memstream(&text, &size);
    if (!stream) return sb_error_set(err, SB_ERR_NOMEM, "out of memory");
    sb_scene_write(scene, stream);
    if (fclose(stream) != 0 || !text) {
        free(text);
        return sb_error_set(err, SB_ERR_NOMEM, "out of memory");
    }
    /* every key but the duration: a run may go on to a longer one */
    char* duration = strstr(text, "\nduration: ");
    size_t cut = duration ? strcspn(duration + 1, "\n") + 1 : 0;
    if (duration) memmove(duration, duration + cut, size - (size_t)(duration - text) - cut + 1);
    *hash = sb_hash(SB_HASH_START, text, strlen(text));
    /* and every file it reads: a mesh edited since is another scene */
    sb_checkpoint_files own = {0}, *list = files ? files : &own;
    sb_status status = scene_files(text, list, err);
    for (uint32_t i = 0; status == SB_OK && i < list->count; i++) {
        *hash = sb_hash(*hash, list->paths[i], strlen(list->paths[i]) + 1);
        *hash = sb_hash(*hash, &list->hashes[i], sizeof list->hashes[i]);
    }
    sb_checkpoint_files_free(&own);
    free(text);
    return status;
}

/* The "RUN " section's values, in order. */
static void run_values(const sb_run_state* run, uint64_t counts[2], double values[8], uint32_t* reason) {
    const sb_stop* s = &run->stop;
    counts[0] = run->frames, counts[1] = run->log_bytes;
    double list[8] = {run->every,  run->next,   s->kinetic_energy, s->min_time,
                      s->max_time, s->duration, s->time,           s->kinetic};
    memcpy(values, list, sizeof list);
    *reason = (uint32_t)s->reason;
}

/* The whole checkpoint into w (counting only without a buffer). */
static bool write_all(sb_sections_writer* w, void* buffer, size_t capacity, uint64_t scene_hash, uint32_t vertex_count,
                      const sb_run_state* run, const sb_solver* solver, size_t state_size) {
    sb_sections_header header = {.version = SB_CHECKPOINT_VERSION,
                                 .real_size = sizeof(sb_real),
                                 .vertex_count = vertex_count,
                                 .hash = scene_hash};
    memcpy(header.magic, SB_CHECKPOINT_MAGIC, 8);
    uint64_t counts[2];
    double values[8];
    uint32_t reason;
    run_values(run, counts, values, &reason);
    sb_sections_begin(w, buffer, capacity, &header);
    sb_sections_open(w, sb_run_tag);
    sb_sections_put(w, counts, sizeof counts);
    sb_sections_put(w, values, sizeof values);
    sb_sections_put(w, &reason, sizeof reason);
    sb_sections_close(w);
    sb_sections_open(w, sb_times_tag);
    sb_sections_put(w, run->times, run->frames * sizeof *run->times);
    sb_sections_close(w);
    if (run->files) {
        sb_sections_open(w, sb_files_tag);
        sb_sections_put(w, &run->files->count, sizeof run->files->count);
        for (uint32_t i = 0; i < run->files->count; i++) {
            uint32_t length = (uint32_t)strlen(run->files->paths[i]);
            sb_sections_put(w, &run->files->hashes[i], sizeof run->files->hashes[i]);
            sb_sections_put(w, &length, sizeof length);
            sb_sections_put(w, run->files->paths[i], length);
        }
        sb_sections_close(w);
    }
    sb_sections_open(w, sb_solver_tag);
    bool fits = w->data && w->size <= w->capacity && state_size <= w->capacity - w->size;
    if (fits) sb_solver_save_state(solver, w->data + w->size, state_size, NULL);
    w->size += state_size;
    sb_sections_close(w);
    return sb_sections_end(w);
}

sb_status sb_checkpoint_write(const char* path, uint64_t scene_hash, uint32_t vertex_count, const sb_run_state* run,
                              const sb_solver* solver, sb_error* err) {
    size_t state_size = sb_solver_state_size(solver);
    sb_sections_writer w;
    write_all(&w, NULL, 0, scene_hash, vertex_count, run, solver, state_size);
    size_t size = w.size;
    void* data = malloc(size);
    if (!data) return sb_error_set(err, SB_ERR_NOMEM, "%s: out of memory (%zu bytes)", path, size);
    write_all(&w, data, size, scene_hash, vertex_count, run, solver, state_size);
    sb_atomic_file file;
    sb_status status = sb_atomic_open(&file, path, err);
    if (status == SB_OK) {
        sb_atomic_write(&file, data, size);
        status = sb_atomic_commit(&file, err);
    }
    free(data);
    return status;
}

/* Every value of the "RUN " section in range, or a message naming the
 * first that is not (a checkpoint whose checksum was recomputed is
 * otherwise trusted: a NaN duration made --resume hang, log_bytes 0 cut
 * log.csv to nothing). */
static sb_status check_run(const char* path, const uint64_t counts[2], const double v[8], uint32_t reason,
                           uint64_t max_frames, sb_error* err) {
    static const char* const names[8] = {"the checkpoint interval", "the next checkpoint's time",
                                         "stop.kinetic_energy",     "stop.min_time",
                                         "stop.max_time",           "stop.duration",
                                         "the stop's time",         "the stop's kinetic energy"};
    if (counts[0] < 1 || counts[0] > max_frames)
        return sb_error_set(err, SB_ERR_PARSE, "%s: the run's state is out of range (%llu frames, at most %llu)", path,
                            (unsigned long long)counts[0], (unsigned long long)max_frames);
    /* log.csv: a header line and a line per frame, each at least two bytes */
    if (counts[1] < 2 * (counts[0] + 1) || counts[1] > ((uint64_t)1 << 50))
        return sb_error_set(err, SB_ERR_PARSE,
                            "%s: the run's state is out of range (log.csv's length %llu bytes for %llu frames)", path,
                            (unsigned long long)counts[1], (unsigned long long)counts[0]);
    if (reason > SB_STOP_DURATION)
        return sb_error_set(err, SB_ERR_PARSE, "%s: the run's state is out of range (stop reason %u)", path, reason);
    for (int k = 0; k < 8; k++) {
        bool ok = isfinite(v[k]) && v[k] >= 0 && v[k] < 1e15;
        if (k == 0 || k == 5) ok = ok && v[k] > 0; /* the interval and the duration */
        if (!ok)
            return sb_error_set(err, SB_ERR_PARSE, "%s: the run's state is out of range (%s = %g)", path, names[k],
                                v[k]);
    }
    return SB_OK;
}

/* The "RUN " section into run (times not yet). */
static sb_status read_run(const char* path, const sb_sections_reader* r, uint64_t max_frames, sb_run_state* run,
                          sb_error* err) {
    sb_cursor c;
    uint64_t counts[2];
    double v[8];
    uint32_t reason;
    if (!sb_sections_find(r, sb_run_tag, &c) || !sb_cursor_take(&c, counts, sizeof counts) ||
        !sb_cursor_take(&c, v, sizeof v) || !sb_cursor_take(&c, &reason, sizeof reason))
        return sb_error_set(err, SB_ERR_PARSE, "%s: no whole RUN section", path);
    sb_status status = check_run(path, counts, v, reason, max_frames, err);
    if (status != SB_OK) return status;
    *run = (sb_run_state){.frames = counts[0], .log_bytes = counts[1], .every = v[0], .next = v[1]};
    run->stop = (sb_stop){.kinetic_energy = v[2],
                          .min_time = v[3],
                          .max_time = v[4],
                          .duration = v[5],
                          .reason = (sb_stop_reason)reason,
                          .time = v[6],
                          .kinetic = v[7]};
    return SB_OK;
}

static sb_status read_times(const char* path, const sb_sections_reader* r, sb_run_state* run, sb_error* err) {
    sb_cursor c;
    size_t bytes = run->frames * sizeof *run->times;
    if (!sb_sections_find(r, sb_times_tag, &c) || c.left != bytes)
        return sb_error_set(err, SB_ERR_PARSE, "%s: the frame times do not match the %llu frames", path,
                            (unsigned long long)run->frames);
    if (!(run->times = malloc(bytes))) return sb_error_set(err, SB_ERR_NOMEM, "%s: out of memory", path);
    sb_cursor_take(&c, run->times, bytes);
    for (uint64_t k = 0; k < run->frames; k++)
        if (!(isfinite(run->times[k]) && run->times[k] >= (k > 0 ? run->times[k - 1] : 0.0)))
            return sb_error_set(err, SB_ERR_PARSE,
                                "%s: the run's state is out of range (frame %llu's time %g, not finite or before the "
                                "frame before)",
                                path, (unsigned long long)k, run->times[k]);
    return SB_OK;
}

/* A file the checkpoint's "FILE" section lists whose bytes are not those
 * it was written with (now), or NULL. */
static const char* changed_file(const sb_sections_reader* r, char* name, size_t capacity) {
    sb_cursor c;
    uint32_t count;
    if (!sb_sections_find(r, sb_files_tag, &c) || !sb_cursor_take(&c, &count, sizeof count)) return NULL;
    for (uint32_t i = 0; i < count && i < SB_CHECKPOINT_FILES_MAX; i++) {
        uint64_t saved, now;
        uint32_t length;
        if (!sb_cursor_take(&c, &saved, sizeof saved) || !sb_cursor_take(&c, &length, sizeof length) ||
            length >= capacity || !sb_cursor_take(&c, name, length))
            return NULL;
        name[length] = '\0';
        if (strlen(name) != length) return NULL;
        sb_error ignored;
        if (hash_file(name, &now, &ignored) != SB_OK || now != saved) return name;
    }
    return NULL;
}

static sb_status check_header(const char* path, const sb_sections_reader* r, uint64_t scene_hash, uint32_t vertex_count,
                              sb_error* err) {
    const sb_sections_header* h = &r->header;
    if (h->real_size != sizeof(sb_real))
        return sb_error_set(err, SB_ERR_INVALID, "%s: written by a %s build of softbond, this one is %s", path,
                            h->real_size == 8 ? "double" : "float", sizeof(sb_real) == 8 ? "double" : "float");
    char name[4096];
    const char* changed = h->hash != scene_hash ? changed_file(r, name, sizeof name) : NULL;
    if (changed)
        return sb_error_set(err, SB_ERR_INVALID,
                            "%s: written for another scene (%s has changed since: a resumed run would match neither)",
                            path, changed);
    if (h->hash != scene_hash)
        return sb_error_set(err, SB_ERR_INVALID, "%s: written for another scene (a key other than duration differs)",
                            path);
    if (h->vertex_count != vertex_count)
        return sb_error_set(err, SB_ERR_INVALID, "%s: written for a mesh of %u vertices, this one has %u", path,
                            h->vertex_count, vertex_count);
    return SB_OK;
}

static sb_status read_checked(const char* path, const uint8_t* data, size_t size, uint64_t scene_hash,
                              uint32_t vertex_count, uint64_t max_frames, sb_run_state* run, sb_solver* solver,
                              sb_error* err) {
    sb_sections_reader r;
    sb_cursor state;
    sb_status status = sb_sections_read(&r, data, size, SB_CHECKPOINT_MAGIC, SB_CHECKPOINT_VERSION, path, err);
    if (status == SB_OK) status = check_header(path, &r, scene_hash, vertex_count, err);
    if (status == SB_OK) status = read_run(path, &r, max_frames, run, err);
    if (status == SB_OK) status = read_times(path, &r, run, err);
    if (status == SB_OK && !sb_sections_find(&r, sb_solver_tag, &state))
        status = sb_error_set(err, SB_ERR_PARSE, "%s: no solver state", path);
    if (status == SB_OK && sb_solver_load_state(solver, state.at, state.left, err) != SB_OK)
        status = sb_error_prefix(err, SB_ERR_PARSE, path);
    if (status != SB_OK) {
        free(run->times);
        run->times = NULL;
    }
    return status;
}

sb_status sb_checkpoint_read(const char* path, uint64_t scene_hash, uint32_t vertex_count, uint64_t max_frames,
                             sb_run_state* run, sb_solver* solver, sb_error* err) {
    size_t size = 0;
    uint8_t* data = NULL;
    *run = (sb_run_state){0};
    sb_status status = read_bytes(path, &data, &size, err);
    if (status == SB_OK)
        status = read_checked(path, data, size, scene_hash, vertex_count, max_frames, run, solver, err);
    free(data);
    return status;
}
