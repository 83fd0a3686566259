// A probe the tests and scripts use to tell a drawing from a blank canvas.

/**
 * Luminance variance of a canvas (WebGL or 2D), over every 7th pixel: near zero for a
 * blank frame. A WebGL canvas must keep its drawing buffer (preserveDrawingBuffer) or
 * be read in the task that drew it.
 */
export function canvasVariance(src) {
  const c = document.createElement('canvas');
  c.width = src.width; c.height = src.height;
  const g = c.getContext('2d');
  g.drawImage(src, 0, 0);
  const px = g.getImageData(0, 0, c.width, c.height).data;
  let sum = 0, sum2 = 0, n = 0;
  for (let i = 0; i < px.length; i += 4 * 7) {
    const y = 0.299 * px[i] + 0.587 * px[i + 1] + 0.114 * px[i + 2];
    sum += y; sum2 += y * y; n++;
  }
  return sum2 / n - (sum / n) ** 2;
}
