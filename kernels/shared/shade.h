/* The shade modes of shade.cl, passed by the host (host/render/shading.cpp) as its `mode`
   argument: one number per ShadeMode. */
#ifndef CLVIS_SHARED_SHADE_H
#define CLVIS_SHARED_SHADE_H

#define CLVIS_SHADE_LAMBERT 0 /* Lambert or facing ratio with a directional light */
#define CLVIS_SHADE_DEPTH 1   /* view depth, near white to far black */
#define CLVIS_SHADE_IDS 2     /* a false colour per triangle id */

#endif
