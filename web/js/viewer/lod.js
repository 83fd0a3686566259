// Level of detail for twigs (mesh.h, Twig lines): where the thickest twig is under
// TWIG_LINE_PX pixels wide at the distance of the orbit target, draw the twigs' lines
// instead of their prisms. A 1-px line is then what the prism rasterizes to anyway, for
// a third of the work (a 10k-internode tree: 8.5k segments against 37k triangles). The
// prisms stay pickable (picking asks them whatever is drawn).
import * as THREE from 'three';

/** Twigs at most this many pixels wide are drawn as lines. */
export const TWIG_LINE_PX = 1.5;

/** Shows the twigs' lines or their prisms, for the viewer's camera; before each frame. */
export function chooseTwigDetail(viewer) {
  const lines = viewer.twigLines.length > 0 && viewer.showBark && twigPixels(viewer) < TWIG_LINE_PX;
  viewer.twigLinesShown = lines;
  for (const l of viewer.twigLines) l.visible = lines;
  for (const m of viewer.barkMeshes) m.visible = viewer.showBark && !(lines && m.userData.twig);
}

/** How many pixels wide the thickest twig is at the orbit target's distance. */
function twigPixels({ camera, controls, renderer, twigDiameter }) {
  const dist = camera.position.distanceTo(controls.target);
  const h = renderer.domElement.height;
  return twigDiameter * h / (2 * Math.tan(THREE.MathUtils.degToRad(camera.fov / 2)) * Math.max(dist, 1e-6));
}
