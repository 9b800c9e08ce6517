// OpenHRP VRML97 models read in C++, in memory: the paper's ModelParser.
//
// An OpenHRP model file (PROTOs Humanoid, Joint, Segment, ForceSensor, Gyro, AccelerationSensor,
// VisionSensor; Transform/Shape geometry: Box, Cylinder, Sphere, IndexedFaceSet) is parsed
// (PROTO declarations with their defaults, DEF/USE, nested children, comments, MF values) and
// turned into MJCF text, which MuJoCo loads from a virtual file system: no temporary file.
// Several files make one scene through VRML's own `Inline { url "other.wrl" }` at the top level
// of a file (urls relative to the including file), e.g. a robot and a floor.
//
// What the conversion does (docs/vrml.md has the full list; mjcf/hrp1s/README.md the
// SampleRobot facts): each Joint is a body named after its DEF name; jointType free, rotate,
// slide, fixed; a Joint with a jointId is driven by a <motor> (actuators in jointId order);
// armature = rotorInertia * gearRatio^2; a Joint without a jointId is passive, and a passive
// BUSH joint (OpenHRP's rubber bush) is a spring-damper; Segments are the <inertial>; ForceSensor
// -> site + <force>/<torque>; Gyro + AccelerationSensor -> site `imu` + <gyro>/<accelerometer>/
// <framequat>; VisionSensor -> <camera>. A Humanoid whose root Joint is "fixed" (floor.wrl,
// box.wrl) is static scenery whose geoms all collide.
//
// Errors name the file, the line and the column ("file:12:5: ...") and what would work; no
// input makes these functions crash, throw or exit.
#pragma once

#include <mujoco/mujoco.h>

#include <string>

namespace ohrp::vrml {

// True when `path` names a VRML file (ends in ".wrl", any case).
bool IsVrmlPath(const std::string& path);

// Converts the VRML97 text `text` to MJCF. `file` names the text in messages and is the base of
// relative Inline urls (Inline files are read from disk). Returns false and sets `*error`
// ("file:line:column: what; what would work") when the text is malformed or the model cannot be
// represented; `*mjcf` is then unspecified.
bool ConvertText(const std::string& text, const std::string& file, std::string* mjcf,
                 std::string* error);

// Reads `path` and converts it (ConvertText).
bool ConvertFile(const std::string& path, std::string* mjcf, std::string* error);

// Loads a VRML file into a MuJoCo model through MuJoCo's virtual file system. Returns the model
// (the caller owns it: mj_deleteModel) or null with `*error` set (the VRML position, or MuJoCo's
// text about the generated MJCF, prefixed by the file name).
mjModel* LoadModel(const std::string& path, std::string* error);

}  // namespace ohrp::vrml
