/* formats/vox_write.c - MagicaVoxel writer (being written). */
#include "formats/vox.h"
