/* albatros.h — libalbatros, the golden model of the Albatros half-plane
 * video processor: the GP, the VP at three fidelities, the step-and-compare
 * model a testbench drives, the sinks and the host side of the USB bridge.
 * One header for all of it; docs/architecture.md draws the layers and
 * docs/cosim.md is the contract a testbench builds on. */
#ifndef ALBATROS_H
#define ALBATROS_H

#include "diag.h"
#include "dpi.h"
#include "dump.h"
#include "exr.h"
#include "file.h"
#include "json.h"
#include "frame.h"
#include "gp.h"
#include "link.h"
#include "model.h"
#include "preview.h"
#include "profile.h"
#include "scene.h"
#include "sim.h"
#include "stream.h"
#include "transport.h"
#include "vcd.h"
#include "vec3.h"
#include "vp.h"
#include "words.h"

/* The version of the headers; alb_version() is the library's, which a
 * program linked against the shared library may see change under it. */
#define ALB_VERSION_MAJOR 0
#define ALB_VERSION_MINOR 1
#define ALB_VERSION_PATCH 0
#define ALB_VERSION_STRING "0.1.0"

#pragma GCC visibility push(default)
#ifdef __cplusplus
extern "C" {
#endif
const char *alb_version(void);
#ifdef __cplusplus
}
#endif
#pragma GCC visibility pop

#endif
