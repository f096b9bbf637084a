// BAKER_text: the glyph quads shaded from the distance-field atlas (fill, outline, glow, shadow); premultiplied
// alpha out (blend ONE, ONE_MINUS_SRC_ALPHA).
uniform sampler2D u_atlas;
uniform vec4 u_color;
uniform float u_softness;
uniform vec4 u_outlineColor;
uniform float u_outlineWidth;
uniform vec4 u_glowColor;
uniform float u_glowWidth;
uniform vec4 u_shadowColor;
uniform float u_shadowSoftness;
uniform int u_fieldType;
uniform float u_distanceRange;
uniform vec2 u_shadowOffset;
varying vec2 vUvText;
void main() {
	BakerTextStyle style = BakerTextStyle(u_color, u_softness, u_outlineColor, u_outlineWidth, u_glowColor, u_glowWidth,
		u_shadowColor, u_shadowSoftness);
	vec2 atlasSize = vec2(textureSize(u_atlas, 0));
	float range = baker_text_screen_px_range(u_distanceRange, atlasSize, fwidth(vUvText));
	vec4 texel = texture(u_atlas, vUvText);
	vec4 shadowTexel = texture(u_atlas, vUvText - u_shadowOffset);
	vec4 color = baker_text_shade(style, texel, shadowTexel, u_fieldType, u_distanceRange, range);
	if (color.a <= 0.0) discard;
	gl_FragColor = color;
}
