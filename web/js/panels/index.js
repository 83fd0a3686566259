// The side panels, in page order. A panel is a class constructed with
// ctx = {viewer, session} (it wires its own controls there) whose instance has:
//   id                  a name
//   show(summary)       optional: a summary of the session arrived (any edit, or opening)
//   loaded(lastLoad)    optional: a new snapshot is drawn (viewer.lastLoad)
//   presets(reply)      optional: GET /v1/presets answered ({presets, parameters})
//   keys                optional: {key: (keydown event) => void}, keys in lower case
//   edited(edits)       optional: the page sent these edits and meristemd accepted them
// A model's own panel (its parameters, an editor) is a new file listed here; its section
// in index.html says which models show it (data-models, models.js).
import { GrowthPanel } from './growth.js';
import { ViewPanel } from './view.js';
import { SchedulePanel } from './schedule.js';
import { ParamsPanel } from './params.js';
import { HistoryPanel } from './history.js';
import { TimePanel } from './time.js';
import { LSystemPanel } from './lsystem.js';
import { InversePanel } from './inverse.js';

export const PANELS = [GrowthPanel, TimePanel, LSystemPanel, InversePanel, HistoryPanel, ViewPanel,
  SchedulePanel, ParamsPanel];
