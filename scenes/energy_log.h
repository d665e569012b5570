/* The per-frame energy log of a run, kept in memory and written as
 * log.csv: time,kinetic,bond,angle,stretch_bend,spring,bend,gravity,total. */
#ifndef SB_ENERGY_LOG_H
#define SB_ENERGY_LOG_H

#include "softbond/softbond.h"

typedef struct sb_energy_log {
    double* times;
    sb_energies* energies;
    uint32_t count, capacity;
} sb_energy_log;

/* Returns false when out of memory. */
bool sb_energy_log_add(sb_energy_log* log, double time, const sb_energies* energies);
void sb_energy_log_free(sb_energy_log* log);
/* One row per frame, 17 significant digits; written atomically. */
sb_status sb_energy_log_write(const sb_energy_log* log, const char* path, sb_error* err);

#endif
