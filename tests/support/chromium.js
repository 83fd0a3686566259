'use strict';
// How the browser tests start Debian's Chromium: headless, software GL (SwiftShader),
// no network side traffic; a 1280×800 page with a DevTools session for pen and
// modifier-key input.
const { chromium } = require('playwright-core');

const CHROMIUM_ARGS = ['--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
  '--disable-background-networking', '--disable-component-update', '--disable-sync',
  '--use-angle=swiftshader', '--enable-unsafe-swiftshader'];

/** Launches $CHROMIUM: resolves to {browser, page, cdp}. */
async function openPage() {
  if (!process.env.CHROMIUM) throw new Error('CHROMIUM is not set; configure found no chromium');
  const browser = await chromium.launch({ executablePath: process.env.CHROMIUM, headless: true, args: CHROMIUM_ARGS });
  const page = await browser.newPage({ viewport: { width: 1280, height: 800 } });
  const cdp = await page.context().newCDPSession(page);
  return { browser, page, cdp };
}

module.exports = { CHROMIUM_ARGS, openPage };
