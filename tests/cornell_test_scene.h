/* Pieces of the renderer tests' small Cornell box (pbrt-v3's units): its camera, and after
 * WorldBegin its ceiling light with the floor and back wall; the tests add the film, sampler,
 * integrator, and the sphere or other walls they need. */
#ifndef CLR_CORNELL_TEST_SCENE_H
#define CLR_CORNELL_TEST_SCENE_H

#define CORNELL_CAMERA \
  "LookAt 278 273 -800  278 273 0  0 1 0\nCamera \"perspective\" \"float fov\" [39.3]\n"

#define CORNELL_LIGHT_FLOOR_AND_BACK_WALL                                                    \
  "AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [17 12 4]\n"                        \
  "Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3]\n"                               \
  "\"point P\" [343 548.7 227  343 548.7 332  213 548.7 332  213 548.7 227]\nAttributeEnd\n" \
  "Material \"matte\" \"rgb Kd\" [0.7 0.6 0.5]\n"                                            \
  "Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3  4 5 6 4 6 7]\n"                  \
  "\"point P\" [0 0 0  0 0 559  556 0 559  556 0 0  0 0 559  0 548 559  556 548 559  556 0 559]\n"

#endif
