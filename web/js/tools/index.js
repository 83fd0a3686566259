// The tools, in the order of their buttons. A tool is a class constructed with
// ctx = {viewer, session}; input.js routes the canvas's pointer events to the active
// one. Its instance has:
//   id, key             a name (its button's data-tool) and a keyboard key (lower case)
//   icon, label, title  its button
//   hint                the line shown over the view while it is active
//   buttons             optional: OrbitControls mouseButtons while it is active
//                       (default: the left button is the tool's, the right one orbits)
//   begin(e)            optional: left button down on the canvas; true takes the
//                       gesture (the pointer is captured until it ends)
//   move(e)             optional: the pointer moved during the gesture
//   end(e, {moved})     optional: the gesture ended (pointerup or pointercancel);
//                       moved: the pointer went more than 4 px from where it began
//   hover(e), leave()   optional: the pointer moved with no button down; it left the
//                       canvas, or the tool was put down
//   busy()              optional: a gesture is under way (the camera stays put)
//   loaded()            optional: a new snapshot is drawn
//   models              optional: the growth models it applies to (default: all);
//                       its button is hidden for the others (models.js)
// A new tool is a new file listed here.
import { ViewTool } from './view.js';
import { BrushTool } from './brush.js';
import { PruneTool } from './prune.js';
import { BendTool } from './bend.js';

export const TOOLS = [ViewTool, BrushTool, PruneTool, BendTool];
