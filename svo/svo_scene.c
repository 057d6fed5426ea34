/* svo/svo_scene.c - scene helpers (being written). */
#include "svo/svo.h"
