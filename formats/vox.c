/* formats/vox.c - MagicaVoxel reader (being written). */
#include "formats/vox.h"
