#version 450
// Depth only: the rasteriser writes the depth (the directional notes' simple_depth.frag is empty too).
void main() {}
