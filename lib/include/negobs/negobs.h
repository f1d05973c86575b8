/* negobs umbrella header: includes every public header of the core. */
#ifndef NEGOBS_NEGOBS_H
#define NEGOBS_NEGOBS_H

#include "negobs/status.h"
#include "negobs/fixed.h"
#include "negobs/image.h"
#include "negobs/boxsum.h"
#include "negobs/version.h"

#endif /* NEGOBS_NEGOBS_H */
