// rtpipeline: a miss leaves the payload as the ray-generation shader set it (no hit).
#version 460
#extension GL_EXT_ray_tracing : require

void main() {}
