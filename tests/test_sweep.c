/* softbond sweep and softbond fit, run as a user runs them.
 *
 * Oracles: a free fall's closed form (z = -g T^2 / 2 and a kinetic energy
 * of 4 m g^2 T^2 / 2 for the four vertices of a free sheet: velocity
 * Verlet is exact for a constant force); a mass on a spring's closed form
 * (a handle's force 4 m g (1 - cos(sqrt(k / m) t)) on a sheet dropped on
 * soft handles), from which the fit's target curve is made here; the
 * serial run's own table for the MPI run (bitwise, sorted by case); the
 * solver's blow-up message for the blow-up step; a run at known bond.k and
 * angle.k for the two-constant fit's target (the fit is under test there,
 * not the run). */
#define _POSIX_C_SOURCE 200809L
#include "tests/test_files.h"

#include <dirent.h>
#include <signal.h>
#include <sys/stat.h>
#include <time.h>

#define DATA SB_SOURCE_DIR "/tests/data/sweep"

/* The MPI cases need mpirun (a build with SB_MPI) and no sanitizer:
 * LeakSanitizer takes Open MPI's own allocations in MPI_Init for leaks and
 * fails every rank. */
#if defined(SB_MPIEXEC) && !SB_TEST_SANITIZED
#define MPI_CASES 1
#endif

static int setup_dir(void** state) {
    (void)state;
    return tu_make_tmp_dir("sb_sweep");
}

static int teardown_dir(void** state) {
    (void)state;
    return tu_remove_tmp_dir();
}

static bool exists(const char* path) {
    struct stat info;
    return stat(path, &info) == 0;
}

/* The table's rows (not the header), split into fields; fields[r][f]. */
typedef struct table {
    char* text;
    char* rows[64];
    char* fields[64][16];
    size_t field_count[64];
    size_t count;
} table;

static size_t split(char* line, char** fields, size_t max) {
    size_t n = 0;
    for (char *save, *f = strtok_r(line, ",", &save); f && n < max; f = strtok_r(NULL, ",", &save)) fields[n++] = f;
    return n;
}

/* Reads a table whose fields hold no commas; rows by case number. */
static void read_table(const char* path, table* t) {
    memset(t, 0, sizeof *t);
    t->text = tu_read_file(path);
    assert_non_null(t->text);
    char* save;
    char* line = strtok_r(t->text, "\n", &save); /* the header */
    assert_non_null(line);
    char* lines[64];
    size_t n = 0;
    while ((line = strtok_r(NULL, "\n", &save)) && n < 64) lines[n++] = line;
    for (size_t i = 0; i < n; i++) {
        size_t c = strtoul(lines[i], NULL, 10);
        assert_true(c < 64);
        assert_null(t->rows[c]); /* each case once */
        t->rows[c] = lines[i];
    }
    t->count = n;
    for (size_t c = 0; c < n; c++) {
        assert_non_null(t->rows[c]); /* cases 0 .. n-1 */
        char* copy = strdup(t->rows[c]);
        t->field_count[c] = split(copy, t->fields[c], 16); /* copy kept by fields */
    }
}

static void free_table(table* t) {
    for (size_t c = 0; c < t->count; c++) free(t->fields[c][0]);
    free(t->text);
}

/* Case c's two varied values, "a,b", for comparing designs. */
static const char* t_values(const table* t, size_t c) {
    static char buffers[2][128];
    static int next;
    char* out = buffers[next++ % 2];
    snprintf(out, sizeof buffers[0], "%s,%s", t->fields[c][1], t->fields[c][2]);
    return out;
}

static double number(const table* t, size_t c, size_t field) {
    assert_true(field < t->field_count[c]);
    return strtod(t->fields[c][field], NULL);
}

/* A 3 x 3 grid, duration x gravity: every case's end position and kinetic
 * energy are the closed form's. */
static void test_grid_follows_free_fall(void** state) {
    (void)state;
    tu_result r =
        tu_run((const char*[]){"sweep", DATA "/free_fall_sweep.yaml", "--output", "grid", "--workers", "2", NULL});
    assert_int_equal(r.code, 0);
    TU_ASSERT_CONTAINS(r.out, "9 cases (0 failed)");
    tu_result_free(&r);
    table t;
    read_table(tu_tmp_path("grid/sweep.csv"), &t);
    assert_int_equal(t.count, 9);
    const double durations[3] = {0.05, 0.1, 0.2}, gravities[3] = {-1.0, -2.5, -4.0}, m = 0.01;
    for (size_t c = 0; c < 9; c++) {
        /* case,duration,gravity,z0,kinetic,kinetic_max,status (blew_at empty, message empty) */
        double T = durations[c / 3], g = gravities[c % 3];
        assert_true(number(&t, c, 1) == T);
        assert_true(number(&t, c, 2) == g);
        double z = 0.5 * g * T * T, kinetic = 4.0 * 0.5 * m * g * g * T * T;
        TU_ASSERT_NEAR(number(&t, c, 3), z, 1e-5 * fabs(z) + 1e-7);
        TU_ASSERT_NEAR(number(&t, c, 4), kinetic, 1e-4 * kinetic);
        TU_ASSERT_NEAR(number(&t, c, 5), kinetic, 1e-4 * kinetic); /* it only grows */
        assert_string_equal(t.fields[c][6], "0");                  /* status */
    }
    free_table(&t);
    assert_true(exists(tu_tmp_path("grid/stability.png")) || !exists("/usr/bin/gnuplot"));
    assert_true(exists(tu_tmp_path("grid/z0.png")) || !exists("/usr/bin/gnuplot"));
    assert_false(exists(tu_tmp_path("grid/cases"))); /* no case folder kept */
}

/* Stiff bonds with long steps blow up: those cases are rows with exit 3
 * and the step of the solver's message; the others ran. */
static void test_blowup_is_a_row(void** state) {
    (void)state;
    tu_write_file("blowup.yaml", "scene: " DATA "/stability.yaml\n"
                                 "vary:\n"
                                 "  - {key: bond.k, values: [10, 100000]}\n"
                                 "  - {key: dt, values: [0.0001, 0.01]}\n"
                                 "combine: zip\n"
                                 "metrics: [{name: blew_at, value: blowup_step}]\n"
                                 "keep_outputs: true\n");
    tu_result r = tu_run((const char*[]){"sweep", "blowup.yaml", "--output", "blowup", NULL});
    assert_int_equal(r.code, 0);
    TU_ASSERT_CONTAINS(r.out, "2 cases (1 failed)");
    tu_result_free(&r);
    char* text = tu_read_file(tu_tmp_path("blowup/sweep.csv"));
    assert_non_null(text);
    TU_ASSERT_CONTAINS(text, "case,bond.k,dt,blew_at,status,message\n");
    TU_ASSERT_CONTAINS(text, "\n0,10,0.0001,,0,\n");
    char* row = strstr(text, "\n1,100000,0.01,");
    assert_non_null(row);
    unsigned step, message_step;
    assert_int_equal(sscanf(row, "\n1,100000,0.01,%u,3,step %u (t = ", &step, &message_step), 2);
    assert_int_equal(step, message_step);
    assert_true(step >= 1 && step <= 20); /* 0.2 s at 0.01 s: it blew up within the run */
    /* the solver's own record of the failed case: its kept log stops there */
    assert_true(exists(tu_tmp_path("blowup/cases/000001/log.csv")));
    free(text);
}

static size_t count_lines(const char* path) {
    char* text = tu_read_file(path);
    size_t n = 0;
    for (const char* p = text; p && *p; p++) n += *p == '\n';
    free(text);
    return n;
}

/* A sweep killed midway (SIGKILL once its table holds a few rows), then
 * --resume: every case exactly once; a row left by the killed sweep
 * (marked here) is kept, not run again. */
static void test_killed_sweep_resumes(void** state) {
    (void)state;
    tu_write_file("long.yaml", "scene: " DATA "/free_fall.yaml\n"
                               "set: [dt=0.0001, duration=0.5]\n"
                               "vary: [{key: gravity, format: '[0, 0, %g]', range: {from: -1, to: -12, count: 12}}]\n"
                               "metrics: [{name: z0, vertex: 0, axis: z}]\n");
    const char* csv = tu_tmp_path("long/sweep.csv");
    pid_t pid = fork();
    assert_true(pid >= 0);
    if (pid == 0) {
        bool ok = chdir(tu_tmp_dir) == 0 && freopen("/dev/null", "w", stdout) && freopen("/dev/null", "w", stderr);
        if (ok) execl(SB_PROGRAM, SB_PROGRAM, "sweep", "long.yaml", "--output", "long", (char*)NULL);
        _exit(127);
    }
    while (!exists(csv) || count_lines(csv) < 4) nanosleep(&(struct timespec){0, 2000000}, NULL);
    kill(pid, SIGKILL);
    int status;
    waitpid(pid, &status, 0);
    size_t before = count_lines(csv) - 1;
    assert_true(before >= 3 && before < 12); /* killed midway */
    char* text = tu_read_file(csv);
    /* mark the first row: a resumed sweep that ran case 0 again would lose the mark */
    char* first = strchr(text, '\n') + 1;
    char* end = strchr(first, '\n');
    FILE* f = fopen(csv, "w");
    fwrite(text, 1, (size_t)(end - text), f);
    fputs("kept by resume", f); /* into the row's empty message */
    fputs(end, f);
    fclose(f);
    size_t kept_case = strtoul(first, NULL, 10);
    free(text);
    tu_result r = tu_run((const char*[]){"sweep", "long.yaml", "--resume", "long", NULL});
    assert_int_equal(r.code, 0);
    char expected[64];
    snprintf(expected, sizeof expected, "%zu of 12 cases done", before);
    TU_ASSERT_CONTAINS(r.out, expected);
    tu_result_free(&r);
    table t;
    read_table(csv, &t); /* every case once */
    assert_int_equal(t.count, 12);
    TU_ASSERT_CONTAINS(t.rows[kept_case], "kept by resume");
    for (size_t c = 0; c < 12; c++) {
        double g = -1.0 - (double)c, z = 0.5 * g * 0.25;
        TU_ASSERT_NEAR(number(&t, c, 2), z, 1e-4 * fabs(z));
    }
    free_table(&t);
}

/* The pid of a child of `parent` that is not a zombie, or 0 (a scan of
 * /proc). */
static pid_t live_child_of(pid_t parent) {
    DIR* proc = opendir("/proc");
    assert_non_null(proc);
    pid_t found = 0;
    for (struct dirent* e; !found && (e = readdir(proc));) {
        char path[64], state;
        int ppid;
        snprintf(path, sizeof path, "/proc/%.20s/stat", e->d_name);
        FILE* f = fopen(path, "r");
        if (!f) continue;
        /* pid (comm) state ppid: comm is "softbond" here, no spaces */
        if (fscanf(f, "%*d %*s %c %d", &state, &ppid) == 2 && ppid == parent && state != 'Z')
            found = (pid_t)strtol(e->d_name, NULL, 10);
        fclose(f);
    }
    closedir(proc);
    return found;
}

/* Whether process pid has ended (gone, or a zombie nobody reaped). */
static bool ended(pid_t pid) {
    char path[64], state = 'Z';
    snprintf(path, sizeof path, "/proc/%ld/stat", (long)pid);
    FILE* f = fopen(path, "r");
    if (!f) return true;
    bool read = fscanf(f, "%*d %*s %c", &state) == 1;
    fclose(f);
    return !read || state == 'Z';
}

/* A sweep killed while a case runs (a run of about 10 s here) leaves no
 * run behind: within 2 s its run has ended too. A run left going would
 * write into its case's folder while --resume ran the case again there
 * (and one of the two failed on the other's files). */
static void test_killed_sweep_ends_its_runs(void** state) {
    (void)state;
    tu_write_file("slow.yaml", "scene: " DATA "/free_fall.yaml\n"
                               "set: [dt=0.000001, duration=4]\n"
                               "vary: [{key: gravity, format: '[0, 0, %g]', range: {from: -1, to: -2, count: 2}}]\n"
                               "metrics: [{name: z0, vertex: 0, axis: z}]\n");
    pid_t sweep = fork();
    assert_true(sweep >= 0);
    if (sweep == 0) {
        bool ok = chdir(tu_tmp_dir) == 0 && freopen("/dev/null", "w", stdout) && freopen("/dev/null", "w", stderr);
        if (ok) execl(SB_PROGRAM, SB_PROGRAM, "sweep", "slow.yaml", "--output", "slow", "--workers", "1", (char*)NULL);
        _exit(127);
    }
    pid_t run = 0;
    for (int waited = 0; !(run = live_child_of(sweep)) && waited < 10000; waited++)
        nanosleep(&(struct timespec){0, 1000000}, NULL);
    assert_true(run > 0); /* the sweep started its first case within 10 s */
    kill(sweep, SIGKILL);
    int status;
    waitpid(sweep, &status, 0);
    for (int waited = 0; !ended(run) && waited < 2000; waited++) nanosleep(&(struct timespec){0, 1000000}, NULL);
    if (!ended(run)) {
        kill(run, SIGKILL);
        fail_msg("the run %ld of a killed sweep was still going 2 s after it", (long)run);
    }
}

/* The same 3 x 3 grid under mpirun with 3 ranks (rank 0 hands out, two
 * run): the table sorted by case is bitwise the serial one's. */
static void test_mpi_farm_matches_serial(void** state) {
    (void)state;
#ifdef MPI_CASES
    tu_result r = tu_run((const char*[]){"sweep", DATA "/free_fall_sweep.yaml", "--output", "serial", NULL});
    assert_int_equal(r.code, 0);
    tu_result_free(&r);
    char command[2048];
    snprintf(command, sizeof command,
             "cd '%s' && OMPI_MCA_btl=self,vader OMPI_MCA_btl_vader_single_copy_mechanism=none "
             "OMPI_MCA_rmaps_base_oversubscribe=1 '%s' --allow-run-as-root --oversubscribe -np 3 '%s' sweep '%s' "
             "--output mpi > mpi.out 2> mpi.err",
             tu_tmp_dir, SB_MPIEXEC, SB_PROGRAM, DATA "/free_fall_sweep.yaml");
    int status = system(command);
    char* out = tu_read_file(tu_tmp_path("mpi.out"));
    if (status != 0) fail_msg("mpirun failed (%d): %s", status, tu_read_file(tu_tmp_path("mpi.err")));
    TU_ASSERT_CONTAINS(out, "9 cases (0 failed)");
    TU_ASSERT_CONTAINS(out, "over MPI ranks");
    free(out);
    table serial, mpi;
    read_table(tu_tmp_path("serial/sweep.csv"), &serial);
    read_table(tu_tmp_path("mpi/sweep.csv"), &mpi);
    assert_int_equal(mpi.count, 9);
    for (size_t c = 0; c < 9; c++) assert_string_equal(mpi.rows[c], serial.rows[c]);
    free_table(&serial);
    free_table(&mpi);
#else
    skip();
#endif
}

#ifdef MPI_CASES
/* mpirun's first child process (a rank), or 0. */
static pid_t first_child(pid_t parent) {
    char path[64];
    snprintf(path, sizeof path, "/proc/%d/task/%d/children", (int)parent, (int)parent);
    FILE* f = fopen(path, "r");
    int child = 0;
    if (f) {
        if (fscanf(f, "%d", &child) != 1) child = 0;
        fclose(f);
    }
    return (pid_t)child;
}
#endif

/* A rank killed midway under mpirun -np 3: Open MPI ends the job and says
 * which rank died; the table left is whole, and --resume runs the lost
 * cases: every case exactly once. */
static void test_dead_rank_reported_and_redone(void** state) {
    (void)state;
#ifdef MPI_CASES
    tu_write_file("ranks.yaml", "scene: " DATA "/free_fall.yaml\n"
                                "set: [dt=0.00002, duration=0.5]\n"
                                "vary: [{key: gravity, format: '[0, 0, %g]', range: {from: -1, to: -12, count: 12}}]\n"
                                "metrics: [{name: z0, vertex: 0, axis: z}]\n");
    const char* csv = tu_tmp_path("ranks/sweep.csv");
    pid_t pid = fork();
    assert_true(pid >= 0);
    if (pid == 0) {
        bool ok = chdir(tu_tmp_dir) == 0 && freopen("/dev/null", "w", stdout) && freopen("mpirun.err", "w", stderr) &&
                  setenv("OMPI_MCA_btl", "self,vader", 1) == 0 &&
                  setenv("OMPI_MCA_btl_vader_single_copy_mechanism", "none", 1) == 0;
        if (ok)
            execl(SB_MPIEXEC, SB_MPIEXEC, "--allow-run-as-root", "--oversubscribe", "-np", "3", SB_PROGRAM, "sweep",
                  "ranks.yaml", "--output", "ranks", (char*)NULL);
        _exit(127);
    }
    while (!exists(csv) || count_lines(csv) < 3) nanosleep(&(struct timespec){0, 2000000}, NULL);
    pid_t rank = first_child(pid);
    assert_true(rank > 0);
    kill(rank, SIGKILL);
    int status;
    assert_int_equal(waitpid(pid, &status, 0), pid);
    assert_true(WIFEXITED(status) && WEXITSTATUS(status) != 0); /* the job ended */
    char* err = tu_read_file(tu_tmp_path("mpirun.err"));
    TU_ASSERT_CONTAINS(err, "exited on signal 9");
    free(err);
    size_t before = count_lines(csv) - 1;
    assert_true(before >= 2 && before < 12);
    tu_result r = tu_run((const char*[]){"sweep", "ranks.yaml", "--resume", "ranks", NULL});
    assert_int_equal(r.code, 0);
    tu_result_free(&r);
    table t;
    read_table(csv, &t); /* every case once */
    assert_int_equal(t.count, 12);
    free_table(&t);
#else
    skip();
#endif
}

/* The fit recovers the handle's stiffness and the vertex mass used to make
 * the target from the closed form, from a start 3 times each. */
static const double spring_k = 40.0, spring_m = 0.01, spring_g = 9.81;

/* measured.csv from the closed form, and NAME.yaml fitting k and m from a start of k = 120 and m = mass_start. */
static void write_spring_fit(const char* name, double mass_start) {
    const double k = spring_k, m = spring_m, g = spring_g, w = sqrt(k / m);
    FILE* f = fopen(tu_tmp_path("measured.csv"), "w");
    fputs("time,force\n", f);
    for (int i = 1; i <= 25; i++) fprintf(f, "%.17g,%.17g\n", 0.002 * i, 4.0 * m * g * (1.0 - cos(w * 0.002 * i)));
    fclose(f);
    char text[1024];
    snprintf(text, sizeof text,
             "scene: " DATA "/spring_hang.yaml\n"
             "parameters:\n"
             "  - {key: handles, format: '[{name: spring, vertices: [0, 1, 2, 3], stiffness: %%.17g}]',\n"
             "     start: 120, min: 5, max: 500}\n"
             "  - {key: mass, start: %g, min: 0.001, max: 0.1}\n"
             "target: {file: measured.csv, x: time, y: spring_fz}\n",
             mass_start);
    tu_write_file(name, text);
}

/* DIR/fit.txt's keys within 2 % of the closed form's. */
static void assert_fitted(const char* dir) {
    const double k = spring_k, m = spring_m, g = spring_g;
    char path[256];
    snprintf(path, sizeof path, "%s/fit.txt", dir);
    char* text = tu_read_file(tu_tmp_path(path));
    assert_non_null(text);
    double fitted_k, fitted_m, residual;
    assert_int_equal(sscanf(text, "handles: %lf\nmass: %lf\nrms_residual: %lf", &fitted_k, &fitted_m, &residual), 3);
    TU_ASSERT_NEAR(fitted_k, k, 0.02 * k);
    TU_ASSERT_NEAR(fitted_m, m, 0.02 * m);
    TU_ASSERT_LE(residual, 1e-3 * 4.0 * m * g);
    free(text);
}

static void test_fit_recovers_spring_and_mass(void** state) {
    (void)state;
    write_spring_fit("fit.yaml", 0.03);
    tu_result r = tu_run((const char*[]){"fit", "fit.yaml", "--output", "fit", NULL});
    if (r.code != 0) fail_msg("fit failed: %s", r.err);
    tu_result_free(&r);
    assert_fitted("fit");
    assert_true(exists(tu_tmp_path("fit/fit_curve.csv")));
}

/* Column NAME of a log.csv into values, at most max rows; the row count. */
static size_t log_column(const char* path, const char* name, double* values, size_t max) {
    char* text = tu_read_file(path);
    assert_non_null(text);
    char *save, *line = strtok_r(text, "\n", &save);
    long column = -1, i = 0;
    for (char *fsave, *f = strtok_r(line, ",", &fsave); f; f = strtok_r(NULL, ",", &fsave), i++)
        if (strcmp(f, name) == 0) column = i;
    assert_true(column >= 0);
    size_t n = 0;
    while ((line = strtok_r(NULL, "\n", &save)) && n < max) {
        char* field = line;
        for (long c = 0; c < column; c++) {
            field = strchr(field, ',');
            assert_non_null(field);
            field++;
        }
        values[n++] = strtod(field, NULL);
    }
    free(text);
    return n;
}

/* The fit recovers a bond stiffness and an angle constant together, from a
 * start 3 times off on each (bond.k 3 times too high, angle.k 3 times too
 * low). The target is a run of bent_corner.yaml at the known bond.k = 50 N/m
 * and angle.k = 1 J: the code under test is the fit, not the run. */
static void test_fit_recovers_bond_and_angle(void** state) {
    (void)state;
    const double bond_k = 50.0, angle_k = 1.0;
    tu_result r = tu_run((const char*[]){"run", DATA "/bent_corner.yaml", "--output", "bent", NULL});
    if (r.code != 0) fail_msg("target run failed: %s", r.err);
    tu_result_free(&r);
    enum { frames = 51 };
    double time[64], force[64], bond[64], angle[64];
    const char* log = tu_tmp_path("bent/log.csv");
    assert_int_equal(log_column(log, "time", time, 64), frames);
    assert_int_equal(log_column(log, "pull_fy", force, 64), frames);
    assert_int_equal(log_column(log, "bond", bond, 64), frames);
    assert_int_equal(log_column(log, "angle", angle, 64), frames);
    /* Both terms carry the load, in shares that change along the path (the
     * angles more at the end of the x leg, t = 0.05 s; the bonds more at the
     * end of the y leg): one force curve can tell the two constants apart. */
    TU_ASSERT_NEAR(time[frames / 2], 0.05, 1e-9);
    assert_true(angle[frames / 2] > bond[frames / 2]);
    assert_true(bond[frames - 1] > angle[frames - 1]);
    FILE* f = fopen(tu_tmp_path("bent_measured.csv"), "w");
    assert_non_null(f);
    fputs("time,force\n", f);
    for (size_t i = 0; i < frames; i++) fprintf(f, "%.17g,%.17g\n", time[i], force[i]);
    fclose(f);
    tu_write_file("bent_fit.yaml", "scene: " DATA "/bent_corner.yaml\n"
                                   "parameters:\n"
                                   "  - {key: bond.k, start: 150, min: 1, max: 1000}\n"
                                   "  - {key: angle.k, start: 0.3333, min: 0.01, max: 10}\n"
                                   "target: {file: bent_measured.csv, x: time, y: pull_fy}\n");
    r = tu_run((const char*[]){"fit", "bent_fit.yaml", "--output", "bent_fit", NULL});
    if (r.code != 0) fail_msg("fit failed: %s", r.err);
    tu_result_free(&r);
    char* text = tu_read_file(tu_tmp_path("bent_fit/fit.txt"));
    assert_non_null(text);
    double fitted_bond, fitted_angle, residual;
    assert_int_equal(
        sscanf(text, "bond.k: %lf\nangle.k: %lf\nrms_residual: %lf", &fitted_bond, &fitted_angle, &residual), 3);
    print_message("fitted bond.k %.9g N/m, angle.k %.9g J, RMS residual %.3g N\n", fitted_bond, fitted_angle, residual);
    TU_ASSERT_NEAR(fitted_bond, bond_k, 0.02 * bond_k);
    TU_ASSERT_NEAR(fitted_angle, angle_k, 0.02 * angle_k);
    free(text);
}

/* Under mpirun each rank searches from its own start and the best wins:
 * from m = 0.0033 (a frequency 3 times too high: one search alone ends in a
 * local minimum there) three ranks still find k and m. */
static void test_fit_over_ranks(void** state) {
    (void)state;
#ifdef MPI_CASES
    write_spring_fit("fit_ranks.yaml", 0.003333);
    char command[2048];
    snprintf(command, sizeof command,
             "cd '%s' && OMPI_MCA_btl=self,vader OMPI_MCA_btl_vader_single_copy_mechanism=none "
             "'%s' --allow-run-as-root --oversubscribe -np 3 '%s' fit fit_ranks.yaml --output fit_ranks "
             "> fit_ranks.out 2> fit_ranks.err",
             tu_tmp_dir, SB_MPIEXEC, SB_PROGRAM);
    if (system(command) != 0) fail_msg("mpirun fit failed: %s", tu_read_file(tu_tmp_path("fit_ranks.err")));
    char* out = tu_read_file(tu_tmp_path("fit_ranks.out"));
    TU_ASSERT_CONTAINS(out, "over the MPI ranks");
    free(out);
    assert_fitted("fit_ranks");
    assert_true(exists(tu_tmp_path("fit_ranks/fit_evaluations_rank2.csv")));
#else
    skip();
#endif
}

/* A Latin hypercube of 8 samples over two log ranges: each key's range,
 * cut into 8 strata (of its logarithm), has one case in each; a random
 * design stays within its ranges; the same seed gives the same cases. */
static void test_sampled_designs(void** state) {
    (void)state;
    const char* design = "scene: " DATA "/free_fall.yaml\n"
                         "set: [duration=0.001]\n"
                         "vary:\n"
                         "  - {key: mass, range: {from: 0.001, to: 1, scale: log}}\n"
                         "  - {key: drag, range: {from: 0.5, to: 2}}\n"
                         "combine: %s\nsamples: 8\nseed: 7\n";
    char text[1024];
    snprintf(text, sizeof text, design, "latin");
    tu_write_file("latin.yaml", text);
    snprintf(text, sizeof text, design, "random");
    tu_write_file("random.yaml", text);
    tu_result r = tu_run((const char*[]){"sweep", "latin.yaml", "--output", "latin", NULL});
    assert_int_equal(r.code, 0);
    tu_result_free(&r);
    r = tu_run((const char*[]){"sweep", "random.yaml", "--output", "random", NULL});
    assert_int_equal(r.code, 0);
    tu_result_free(&r);
    r = tu_run((const char*[]){"sweep", "random.yaml", "--output", "random2", NULL});
    assert_int_equal(r.code, 0);
    tu_result_free(&r);
    table latin, random, again;
    read_table(tu_tmp_path("latin/sweep.csv"), &latin);
    read_table(tu_tmp_path("random/sweep.csv"), &random);
    read_table(tu_tmp_path("random2/sweep.csv"), &again);
    assert_int_equal(latin.count, 8);
    int mass_strata[8] = {0}, drag_strata[8] = {0};
    for (size_t c = 0; c < 8; c++) {
        double mass = number(&latin, c, 1), drag = number(&latin, c, 2);
        int i = (int)floor(8.0 * log(mass / 0.001) / log(1000.0)), j = (int)floor(8.0 * (drag - 0.5) / 1.5);
        assert_true(i >= 0 && i < 8 && j >= 0 && j < 8);
        mass_strata[i]++, drag_strata[j]++;
        double rmass = number(&random, c, 1), rdrag = number(&random, c, 2);
        assert_true(rmass >= 0.001 && rmass <= 1.0 && rdrag >= 0.5 && rdrag <= 2.0);
        assert_string_equal(t_values(&random, c), t_values(&again, c));
    }
    for (int i = 0; i < 8; i++) {
        assert_int_equal(mass_strata[i], 1);
        assert_int_equal(drag_strata[i], 1);
    }
    free_table(&latin);
    free_table(&random);
    free_table(&again);
}

/* `softbond COMMAND FILE` exits 2 with one line naming where. */
static void assert_file_fails(const char* command, const char* text, const char* message) {
    tu_write_file("bad.yaml", text);
    tu_result r = tu_run((const char*[]){command, "bad.yaml", "--output", "never", NULL});
    if (r.code != 2 || !strstr(r.err, message) || strchr(r.err, '\n') != r.err + strlen(r.err) - 1)
        fail_msg("expected exit 2 and one line with '%s', got %d: %s", message, r.code, r.err);
    assert_false(exists(tu_tmp_path("never")));
    tu_result_free(&r);
}

static void test_bad_files_name_file_and_line(void** state) {
    (void)state;
    const char* scene = "scene: " DATA "/free_fall.yaml\n";
    char text[1024];
    snprintf(text, sizeof text, "%svary:\n  - {key: bnd.k, values: [1, 2]}\n", scene);
    assert_file_fails("sweep", text, "bad.yaml:3: key: no scene key 'bnd.k'");
    snprintf(text, sizeof text, "%svary:\n  - {key: dt, values: [1, 2]}\nmetrcs: []\n", scene);
    assert_file_fails("sweep", text, "bad.yaml:4: unknown key 'metrcs' (did you mean 'metrics'?)");
    snprintf(text, sizeof text, "%svary:\n  - {key: dt, range: {from: 0, to: 1, count: 3, scale: log}}\n", scene);
    assert_file_fails("sweep", text, "bad.yaml:3: range: a log scale needs from and to > 0");
    snprintf(text, sizeof text, "%svary:\n  - {key: dt, values: [1, 2]}\n  - {key: mass, values: [1]}\ncombine: zip\n",
             scene);
    assert_file_fails("sweep", text, "bad.yaml:4: combine zip: 'mass' has 1 values");
    snprintf(text, sizeof text, "%svary:\n  - {key: dt, format: '%%s', values: [1]}\n", scene);
    assert_file_fails("sweep", text, "bad.yaml:3: format: expected one number conversion");
    snprintf(text, sizeof text, "%svary: [{key: dt, values: [1]}]\nmetrics:\n  - {name: z, vertex: 0}\n", scene);
    assert_file_fails("sweep", text, "bad.yaml:4: metric: needs axis");
    assert_file_fails("sweep", "scene: x.yaml\nvary: [{key: dt, values: [1]\n", "bad.yaml:3:");
    snprintf(text, sizeof text, "%sset: [dt=-1]\nvary: [{key: mass, values: [1]}]\n", scene);
    assert_file_fails("sweep", text, "bad.yaml: the base scene: --set dt=-1: 'dt' must be > 0");
    snprintf(text, sizeof text,
             "%sparameters: [{key: mass, start: 5, min: 0.1, max: 1}]\ntarget: {file: m.csv, x: a, y: b}\n", scene);
    assert_file_fails("fit", text, "bad.yaml:2: parameter 'mass': expected min < max and start within them");
    snprintf(text, sizeof text, "%sparameters: [{key: mass, start: 1, min: 0.1, max: 10}]\ntarget: {x: a, y: b}\n",
             scene);
    assert_file_fails("fit", text, "bad.yaml:3: target: needs file, x and y");
    /* --resume of a folder that holds no sweep: said, and nothing made */
    tu_result r = tu_run((const char*[]){"sweep", DATA "/free_fall_sweep.yaml", "--resume", "nothere", NULL});
    assert_int_equal(r.code, 2);
    TU_ASSERT_CONTAINS(r.err, "--resume: nothere/sweep.csv: cannot read");
    assert_false(exists(tu_tmp_path("nothere")));
    tu_result_free(&r);
}

/* A misspelt log.csv column cannot be known before a run: the sweep runs,
 * and one line names the metric's line. */
static void test_unknown_column_said(void** state) {
    (void)state;
    tu_write_file("typo.yaml", "scene: " DATA "/free_fall.yaml\n"
                               "vary: [{key: duration, values: [0.01]}]\n"
                               "metrics:\n"
                               "  - {name: k, column: kinetc}\n");
    tu_result r = tu_run((const char*[]){"sweep", "typo.yaml", "--output", "typo", NULL});
    assert_int_equal(r.code, 0);
    TU_ASSERT_CONTAINS(r.err, "typo.yaml:4: metric 'k': no run's log.csv has a column 'kinetc'");
    tu_result_free(&r);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_grid_follows_free_fall),
        cmocka_unit_test(test_blowup_is_a_row),
        cmocka_unit_test(test_killed_sweep_resumes),
        cmocka_unit_test(test_killed_sweep_ends_its_runs),
        cmocka_unit_test(test_mpi_farm_matches_serial),
        cmocka_unit_test(test_fit_recovers_spring_and_mass),
        cmocka_unit_test(test_fit_recovers_bond_and_angle),
        cmocka_unit_test(test_bad_files_name_file_and_line),
        cmocka_unit_test(test_sampled_designs),
        cmocka_unit_test(test_dead_rank_reported_and_redone),
        cmocka_unit_test(test_unknown_column_said),
        cmocka_unit_test(test_fit_over_ranks),
    };
    return cmocka_run_group_tests(tests, setup_dir, teardown_dir);
}
