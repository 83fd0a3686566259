# The brush client: static files served by meristemd. web/node_modules (three.js)
# is installed by the quick start from web/package-lock.json, not shipped.
webdir = $(pkgdatadir)/web
dist_web_DATA = web/index.html web/style.css web/favicon.svg web/package.json web/package-lock.json
