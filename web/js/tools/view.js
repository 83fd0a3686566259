// The View tool: the left button orbits, the right one pans, the wheel zooms.
import * as THREE from 'three';

export class ViewTool {
  id = 'view';
  key = 'v';
  icon = '⟲';
  label = 'View';
  title = 'View: drag to orbit, wheel to zoom (V)';
  hint = 'Drag to orbit · right-drag to pan · wheel to zoom';
  buttons = { LEFT: THREE.MOUSE.ROTATE, MIDDLE: THREE.MOUSE.DOLLY, RIGHT: THREE.MOUSE.PAN };
}
