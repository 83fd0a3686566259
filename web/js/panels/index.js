// The side panels, in page order. A panel is a class constructed with
// ctx = {viewer, session} (it wires its own controls there) whose instance has:
//   id                  a name
//   show(summary)       optional: a summary of the session arrived (any edit, or opening)
//   loaded(lastLoad)    optional: a new snapshot is drawn (viewer.lastLoad)
//   presets(reply)      optional: GET /v1/presets answered ({presets, parameters})
//   keys                optional: {key: (keydown event) => void}, keys in lower case
//   edited(edits)       optional: the page sent these edits and meristemd accepted them
// A model's own panel (its parameters, an editor) is a new file listed here.
import { GrowthPanel } from './growth.js';
import { ViewPanel } from './view.js';
import { SchedulePanel } from './schedule.js';
import { ParamsPanel } from './params.js';
import { HistoryPanel } from './history.js';

export const PANELS = [GrowthPanel, HistoryPanel, ViewPanel, SchedulePanel, ParamsPanel];
