/* commands.h — the subcommands of the albatros driver. */
#ifndef ALBATROS_COMMANDS_H
#define ALBATROS_COMMANDS_H

#include "albatros/gp.h"
#include "albatros/vp.h"
#include "albatros/json.h"

#include <stdio.h>

int cmd_gp(int argc, char **argv);
int cmd_dump(int argc, char **argv);
int cmd_vectors(int argc, char **argv);
int cmd_profiles(int argc, char **argv);
int cmd_render(int argc, char **argv);
int cmd_vp(int argc, char **argv);
int cmd_reference(int argc, char **argv);
int cmd_compare(int argc, char **argv);
int cmd_accuracy(int argc, char **argv);
int cmd_scene(int argc, char **argv);
int cmd_stream(int argc, char **argv);
int cmd_board(int argc, char **argv);
int cmd_stability(int argc, char **argv);
int cmd_method(int argc, char **argv);



/* GP statistics as a JSON object / a readable block. */
void gp_stats_json(alb_json *j, const alb_gp_stats *s);
void gp_stats_text(FILE *f, const alb_gp_stats *s);

#endif
