#version 450
// Depth only: the rasteriser writes the depth (seed 003's simple_depth.frag is empty too).
void main() {}
