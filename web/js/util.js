// Small helpers every module of the page uses.

/** The first element matching a CSS selector. */
export const $ = (sel) => document.querySelector(sel);

/** Resolves after `ms` milliseconds. */
export const sleep = (ms) => new Promise((r) => setTimeout(r, ms));

/** `x` to three decimals, as the page sends coordinates. */
export const round3 = (x) => Math.round(x * 1000) / 1000;
