// SPDX-License-Identifier: LGPL-2.1-or-later
// tinyobjloader's implementation, built here with the sanitizers and
// coverage instead of linking the distribution's uninstrumented library.
#define TINYOBJLOADER_IMPLEMENTATION
#include <tiny_obj_loader.h>
