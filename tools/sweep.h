/* sweep.h — the stability and speed-against-accuracy sweeps of the classic
 * methods and the Albatros configurations over the stress families
 * (docs/stability.md).  Split into independent jobs (one per family, plus
 * the speed sweep) that write CSV; a report step reads the CSVs and writes
 * Markdown tables and gnuplot charts. */
#ifndef ALBATROS_SWEEP_H
#define ALBATROS_SWEEP_H

#include "../common/profile.h"

#include <stdbool.h>
#include <stdio.h>

#define SWEEP_SEVERITIES 4

/* The families and their severities, in order of increasing severity. */
unsigned sweep_family_count(void);
const char *sweep_family(unsigned i);
const double *sweep_severities(unsigned i);

/* One family: every configuration at every severity, seeds 1..seeds;
 * CSV rows to out (with a header).  progress (may be NULL) on a terminal. */
int sweep_family_run(const char *family, const profile_t *p, unsigned seeds, FILE *out,
                     FILE *progress);
/* Speed against accuracy: every configuration and the VP's three
 * fidelities on a fixed set of scenes; CSV rows to out. */
int sweep_speed_run(const profile_t *p, FILE *out, FILE *progress);

/* Read the CSVs of dir and write stability.md, stability.png, speed.md and
 * speed.png there (charts by gnuplot, which must be installed).  Returns 0,
 * or -1 with a message on stderr. */
int sweep_report(const char *dir);

#endif
