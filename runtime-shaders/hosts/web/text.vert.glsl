// BAKER_text: the label's glyph quads as they are.
varying vec2 vUvText;
void main() {
	vUvText = uv;
	gl_Position = baker_clip(position);
}
