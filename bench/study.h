/* The integrator study's parts beyond the two charts of study.c, each
 * writing its own files into the results folder (see study.c). */
#ifndef SB_STUDY_H
#define SB_STUDY_H

#include <stdbool.h>

/* paper_tables.csv and paper_tables.md: Sudhamani & Merriliance's Tables
 * 2.2.1-2.2.3 redone (study_tables.c). */
void study_paper_tables(const char* out, bool quick);
/* model_accuracy.csv: springs alone against springs with angle and
 * stretch-bend terms, under shear and stretch (study_accuracy.c). */
void study_model_accuracy(const char* out, bool quick);
/* lod_accuracy.csv: the default scene's sheet and its simplified levels,
 * error against the full model beside the step's cost (study_lod.c). */
void study_lod_accuracy(const char* out, bool quick);

#endif
