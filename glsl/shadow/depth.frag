#version 330 core
// Depth only (the shadow atlas has no colour attachment).
void main() {}
