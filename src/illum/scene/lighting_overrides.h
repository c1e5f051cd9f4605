// Light a scene from the command line: a sun and a sky added to whatever the scene file
// holds, the same for every command that lights a scene (render, bake, frame, view), and
// the one test of whether a scene has any light at all.
#pragma once

#include <string>

#include "illum/scene/scene.h"

namespace illum {

// "X,Y,Z" or "X,Y,Z,E": a directional light travelling along (X, Y, Z) (as a scene file's
// "direction"), of irradiance E W/m² on a surface facing it (default π: a white Lambertian
// surface facing it shows radiance 1). Throws Error (one line) for anything else, a zero
// direction or a negative or non-finite E.
void add_sun(Scene& scene, const std::string& value);

// "R,G,B" or "V": a uniform sky of that radiance; otherwise the path of an equirectangular
// HDR image (scene/environment.h), read as linear radiance. Replaces the scene's own
// environment, if any. Throws Error naming the value or file for a malformed number, a
// negative radiance, or a missing or undecodable file.
void set_sky(Scene& scene, const std::string& value);

// Whether anything in the scene emits: a light of any kind (emissive surfaces are area
// lights), or an environment.
bool has_any_light(const Scene& scene);

// The one sentence every command that lights a scene gives for a scene without light (a
// warning, or the refusal of a bake that has nothing to solve for), naming the command,
// what follows (`consequence`) and the options that add light.
std::string unlit_scene_message(const Scene& scene, const std::string& command,
                                const std::string& consequence = "the result will be black");

}  // namespace illum
