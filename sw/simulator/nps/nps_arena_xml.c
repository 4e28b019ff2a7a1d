/*
 * Copyright (C) 2026 FINken range-sensor toolkit contributors
 *
 * This file is part of paparazzi.
 *
 * paparazzi is free software; you can redistribute it and/or modify
 * it under the terms of the GNU General Public License as published by
 * the Free Software Foundation; either version 2, or (at your option)
 * any later version.
 *
 * paparazzi is distributed in the hope that it will be useful,
 * but WITHOUT ANY WARRANTY; without even the implied warranty of
 * MERCHANTABILITY or FITNESS FOR A PARTICULAR PURPOSE.  See the
 * GNU General Public License for more details.
 *
 * You should have received a copy of the GNU General Public License
 * along with paparazzi; see the file COPYING.  If not, see
 * <http://www.gnu.org/licenses/>.
 */

/**
 * @file nps_arena_xml.c
 * Arena XML loader (libxml2). Format (docs/arena-and-walls.md):
 *   <arena name flightHeight wallHeight>
 *     <polygon> <point x y/> ... the first point again </polygon>
 *     <walls numSegments wallWidth segmentMass ... />     defaults of every wall
 *     <wall edge="i" .../>                                 overrides for edge i (points i -> i+1)
 *     <copters radius height/>  <sonars beamHalfAngle range offset/>
 *     <floor material>                                    the default floor material (nps_floor.h)
 *       <region material x0 y0 x1 y1/> ...                rectangles of other materials
 *     </floor>
 *     <obstacle height>                                   an interior obstacle (nps_obstacle.h), any number:
 *       <circle x y radius/> or <polygon> <point x y/> ... the first point again </polygon>
 *     </obstacle>
 *   </arena>
 * Every error is "file:line: reason"; unknown elements and attributes are errors.
 */

#include "nps_arena.h"
#include "nps_arena_params.h"

#include <libxml/parser.h>
#include <libxml/tree.h>
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/** State of one load. */
struct loader {
  struct nps_arena_config *cfg;
  const char *path;
  char *err;
  size_t err_len;
  struct nps_wall_params defaults;
};

static int line_of(xmlNodePtr n)
{
  long l = xmlGetLineNo(n);
  return l > 0 && l < INT_MAX ? (int)l : 0;
}

static int is_named(xmlNodePtr n, const char *name)
{
  return n->type == XML_ELEMENT_NODE && strcmp((const char *)n->name, name) == 0;
}

/** Attribute value (caller frees with xmlFree), or NULL. */
static char *attr(xmlNodePtr n, const char *name)
{
  return (char *)xmlGetProp(n, (const xmlChar *)name);
}

/**
 * Parse the attributes of n: those of table into base, the names in extra[] are left to the caller,
 * anything else is an error.
 */
static int parse_attrs(struct loader *ld, xmlNodePtr n, const struct nps_arena_param_table *table, void *base,
                       const char *const *extra)
{
  for (xmlAttrPtr a = n->properties; a; a = a->next) {
    const char *name = (const char *)a->name;
    int is_extra = 0;
    for (int k = 0; extra && extra[k]; k++) {
      is_extra |= strcmp(extra[k], name) == 0;
    }
    if (is_extra) {
      continue;
    }
    const struct nps_arena_param_spec *spec = table ? nps_arena_param_find(table, name) : NULL;
    if (!spec) {
      nps_arena_errf(ld->err, ld->err_len, ld->path, line_of(n), "unknown attribute '%s' on <%s>", name,
                     (const char *)n->name);
      return -1;
    }
    char *text = attr(n, name);
    char why[256];
    int rc = nps_arena_param_parse(spec, text ? text : "", base, why, sizeof why);
    xmlFree(text);
    if (rc != 0) {
      nps_arena_errf(ld->err, ld->err_len, ld->path, line_of(n), "<%s> %s", (const char *)n->name, why);
      return -1;
    }
  }
  return 0;
}

/** Largest length or coordinate of an arena [m]: beyond, no indoor arena (and no row of the logs) holds it. */
#define NPS_ARENA_MAX_LENGTH_M 1e4

/** A required number attribute of at most NPS_ARENA_MAX_LENGTH_M in magnitude. */
static int number_attr(struct loader *ld, xmlNodePtr n, const char *name, double *out)
{
  char *text = attr(n, name);
  char *end = NULL;
  double v = text ? strtod(text, &end) : NAN;
  int ok = text && end != text && *end == '\0' && fabs(v) <= NPS_ARENA_MAX_LENGTH_M;
  if (!ok) {
    if (text) {
      nps_arena_errf(ld->err, ld->err_len, ld->path, line_of(n), "<%s> %s=\"%s\": expected a number of at most "
                     "%g m in magnitude", (const char *)n->name, name, text, NPS_ARENA_MAX_LENGTH_M);
    } else {
      nps_arena_errf(ld->err, ld->err_len, ld->path, line_of(n), "<%s> needs a '%s' attribute",
                     (const char *)n->name, name);
    }
  }
  xmlFree(text);
  *out = v;
  return ok ? 0 : -1;
}

/** Only elements (and blank text, comments) may appear as children. */
static int check_text(struct loader *ld, xmlNodePtr n)
{
  if (n->type == XML_TEXT_NODE || n->type == XML_CDATA_SECTION_NODE) {
    for (const xmlChar *c = n->content; c && *c; c++) {
      if (!strchr(" \t\r\n", *c)) {
        nps_arena_errf(ld->err, ld->err_len, ld->path, line_of(n), "unexpected text in <%s>",
                       (const char *)n->parent->name);
        return -1;
      }
    }
  }
  return 0;
}

/** <polygon> <point x y/> ... </polygon> into a new array of points (*out, *count), as given. */
static int parse_points(struct loader *ld, xmlNodePtr poly, struct nps_arena_point **out, int *count)
{
  static const char *const xy[] = { "x", "y", NULL };
  if (parse_attrs(ld, poly, NULL, NULL, NULL) != 0) {
    return -1;
  }
  int elements = 0;
  for (xmlNodePtr c = poly->children; c; c = c->next) {
    elements += c->type == XML_ELEMENT_NODE;
  }
  *out = calloc((size_t)(elements > 0 ? elements : 1), sizeof **out);
  *count = 0;
  if (!*out) {
    nps_arena_errf(ld->err, ld->err_len, ld->path, line_of(poly), "out of memory");
    return -1;
  }
  for (xmlNodePtr c = poly->children; c; c = c->next) {
    if (check_text(ld, c) != 0) {
      return -1;
    }
    if (c->type != XML_ELEMENT_NODE) {
      continue;
    }
    if (!is_named(c, "point")) {
      nps_arena_errf(ld->err, ld->err_len, ld->path, line_of(c), "unknown element <%s> in <polygon> (expected <point>)",
                     (const char *)c->name);
      return -1;
    }
    struct nps_arena_point *p = &(*out)[*count];
    p->line = line_of(c);
    if (parse_attrs(ld, c, NULL, NULL, xy) != 0 || number_attr(ld, c, "x", &p->x_m) != 0 ||
        number_attr(ld, c, "y", &p->y_m) != 0) {
      return -1;
    }
    (*count)++;
  }
  return 0;
}

static int parse_polygon(struct loader *ld, xmlNodePtr poly)
{
  ld->cfg->polygon_line = line_of(poly);
  return parse_points(ld, poly, &ld->cfg->points, &ld->cfg->num_points);
}

/** An obstacle's <polygon>: closed as the arena's (the last point repeats the first), kept without the repeat. */
static int parse_obstacle_polygon(struct loader *ld, xmlNodePtr poly, struct nps_obstacle *o)
{
  struct nps_arena_point *points = NULL;
  int n = 0;
  if (parse_points(ld, poly, &points, &n) != 0) {
    free(points);
    return -1;
  }
  const struct nps_arena_point *first = &points[0], *last = &points[n > 0 ? n - 1 : 0];
  if (n < 4 || first->x_m != last->x_m || first->y_m != last->y_m) {
    nps_arena_errf(ld->err, ld->err_len, ld->path, n > 0 ? last->line : line_of(poly), "the obstacle's <polygon> "
                   "needs at least 3 corners and a last point repeating the first (%d point(s) given)", n);
    free(points);
    return -1;
  }
  o->num_corners = n - 1;
  o->corners = malloc((size_t)o->num_corners * sizeof * o->corners);
  o->corner_lines = malloc((size_t)o->num_corners * sizeof * o->corner_lines);
  for (int i = 0; o->corners && o->corner_lines && i < o->num_corners; i++) {
    o->corners[i][0] = points[i].x_m;
    o->corners[i][1] = points[i].y_m;
    o->corner_lines[i] = points[i].line;
  }
  free(points);
  if (!o->corners || !o->corner_lines) {
    nps_arena_errf(ld->err, ld->err_len, ld->path, line_of(poly), "out of memory");
    return -1;
  }
  return 0;
}

/** <obstacle height> with one <circle x y radius/> or one <polygon>. */
static int parse_obstacle(struct loader *ld, xmlNodePtr n, struct nps_obstacle *o)
{
  static const char *const height_only[] = { "height", NULL }, *const circle[] = { "x", "y", "radius", NULL };
  o->line = line_of(n);
  if (parse_attrs(ld, n, NULL, NULL, height_only) != 0 || number_attr(ld, n, "height", &o->height_m) != 0) {
    return -1;
  }
  xmlNodePtr shape = NULL;
  for (xmlNodePtr c = n->children; c; c = c->next) {
    if (check_text(ld, c) != 0) {
      return -1;
    }
    if (c->type != XML_ELEMENT_NODE) {
      continue;
    }
    if (shape != NULL || (!is_named(c, "circle") && !is_named(c, "polygon"))) {
      nps_arena_errf(ld->err, ld->err_len, ld->path, line_of(c), "<%s> in <obstacle>: expected one <circle> or one "
                     "<polygon>", (const char *)c->name);
      return -1;
    }
    shape = c;
  }
  if (shape == NULL) {
    nps_arena_errf(ld->err, ld->err_len, ld->path, o->line, "<obstacle> needs a <circle> or a <polygon>");
    return -1;
  }
  if (is_named(shape, "polygon")) {
    o->shape = NPS_OBSTACLE_POLYGON;
    return parse_obstacle_polygon(ld, shape, o);
  }
  o->shape = NPS_OBSTACLE_CIRCLE;
  return parse_attrs(ld, shape, NULL, NULL, circle) != 0 || number_attr(ld, shape, "x", &o->centre_m[0]) != 0 ||
         number_attr(ld, shape, "y", &o->centre_m[1]) != 0 || number_attr(ld, shape, "radius", &o->radius_m) != 0
         ? -1 : 0;
}

/** Every <obstacle> child of root, in file order. */
static int parse_obstacles(struct loader *ld, xmlNodePtr root)
{
  struct nps_arena_config *cfg = ld->cfg;
  int count = 0;
  for (xmlNodePtr c = root->children; c; c = c->next) {
    count += is_named(c, "obstacle");
  }
  if (count == 0) {
    return 0;
  }
  cfg->obstacles = calloc((size_t)count, sizeof * cfg->obstacles);
  if (!cfg->obstacles) {
    nps_arena_errf(ld->err, ld->err_len, ld->path, line_of(root), "out of memory");
    return -1;
  }
  for (xmlNodePtr c = root->children; c; c = c->next) {
    if (is_named(c, "obstacle")) {
      /* counted before parsing, so that a half-parsed obstacle is freed with the configuration */
      if (parse_obstacle(ld, c, &cfg->obstacles[cfg->num_obstacles++]) != 0) {
        return -1;
      }
    }
  }
  return 0;
}

/** The material attribute of n (a name of nps_floor.h) into *out. */
static int material_attr(struct loader *ld, xmlNodePtr n, enum nps_floor_material *out)
{
  char *text = attr(n, "material");
  const enum nps_floor_material m = text ? nps_floor_material_from_name(text) : NPS_FLOOR_NONE;
  if (m == NPS_FLOOR_NONE) {
    if (text) {
      nps_arena_errf(ld->err, ld->err_len, ld->path, line_of(n), "<%s> material=\"%s\": unknown floor material "
                     "(expected %s)", (const char *)n->name, text, nps_floor_material_names());
    } else {
      nps_arena_errf(ld->err, ld->err_len, ld->path, line_of(n), "<%s> needs a 'material' attribute (%s)",
                     (const char *)n->name, nps_floor_material_names());
    }
  }
  xmlFree(text);
  *out = m;
  return m == NPS_FLOOR_NONE ? -1 : 0;
}

/** <region material x0 y0 x1 y1/>: a rectangle of the floor [m]. */
static int parse_region(struct loader *ld, xmlNodePtr n, struct nps_floor_region *r)
{
  static const char *const names[] = { "material", "x0", "y0", "x1", "y1", NULL };
  r->line = line_of(n);
  if (parse_attrs(ld, n, NULL, NULL, names) != 0 || material_attr(ld, n, &r->material) != 0) {
    return -1;
  }
  return number_attr(ld, n, "x0", &r->x0_m) != 0 || number_attr(ld, n, "y0", &r->y0_m) != 0 ||
         number_attr(ld, n, "x1", &r->x1_m) != 0 || number_attr(ld, n, "y1", &r->y1_m) != 0 ? -1 : 0;
}

/** <floor [material]>: the default material (hard when not given) and <region> children. */
static int parse_floor(struct loader *ld, xmlNodePtr n)
{
  static const char *const material_only[] = { "material", NULL };
  struct nps_floor *floor = &ld->cfg->floor;
  floor->line = line_of(n);
  if (parse_attrs(ld, n, NULL, NULL, material_only) != 0 ||
      (xmlHasProp(n, (const xmlChar *)"material") && material_attr(ld, n, &floor->default_material) != 0)) {
    return -1;
  }
  int count = 0;
  for (xmlNodePtr c = n->children; c; c = c->next) {
    count += c->type == XML_ELEMENT_NODE;
  }
  floor->regions = calloc((size_t)(count > 0 ? count : 1), sizeof * floor->regions);
  if (!floor->regions) {
    nps_arena_errf(ld->err, ld->err_len, ld->path, line_of(n), "out of memory");
    return -1;
  }
  for (xmlNodePtr c = n->children; c; c = c->next) {
    if (check_text(ld, c) != 0) {
      return -1;
    }
    if (c->type != XML_ELEMENT_NODE) {
      continue;
    }
    if (!is_named(c, "region")) {
      nps_arena_errf(ld->err, ld->err_len, ld->path, line_of(c), "unknown element <%s> in <floor> (expected <region>)",
                     (const char *)c->name);
      return -1;
    }
    if (parse_region(ld, c, &floor->regions[floor->num_regions]) != 0) {
      return -1;
    }
    floor->num_regions++;
  }
  return 0;
}

/** <wall edge="i" ...>: the edge's parameters start from <walls> and take the given attributes. */
static int parse_wall(struct loader *ld, xmlNodePtr n, int *seen)
{
  static const char *const edge_only[] = { "edge", NULL };
  struct nps_arena_config *cfg = ld->cfg;
  int edges = cfg->num_points - 1;
  char *text = attr(n, "edge");
  char *end = NULL;
  long e = text ? strtol(text, &end, 10) : -1;
  int ok = text && end != text && *end == '\0' && e >= 0 && e < edges;
  if (!ok) {
    if (text) {
      nps_arena_errf(ld->err, ld->err_len, ld->path, line_of(n),
                     "<wall> edge=\"%s\": expected a wall index in [0, %d] (edge i runs from point i to point i+1)",
                     text, edges - 1);
    } else {
      nps_arena_errf(ld->err, ld->err_len, ld->path, line_of(n), "<wall> needs an 'edge' attribute");
    }
    xmlFree(text);
    return -1;
  }
  xmlFree(text);
  if (seen[e]) {
    nps_arena_errf(ld->err, ld->err_len, ld->path, line_of(n), "<wall> edge=\"%ld\" is given twice (first at line %d)",
                   e, seen[e]);
    return -1;
  }
  seen[e] = line_of(n);
  struct nps_wall_params *p = &cfg->walls[e];
  p->line = line_of(n);
  return parse_attrs(ld, n, &nps_arena_wall_table, p, edge_only);
}

/** Root children: each once except <wall>; <polygon> and <walls> first so <wall> can use them. */
static int parse_children(struct loader *ld, xmlNodePtr root)
{
  static const char *const once[] = { "polygon", "walls", "copters", "sonars", "floor" };
  enum { ONCE = sizeof once / sizeof once[0] };
  xmlNodePtr first[ONCE] = { NULL, NULL, NULL, NULL, NULL };
  struct nps_arena_config *cfg = ld->cfg;
  for (xmlNodePtr c = root->children; c; c = c->next) {
    if (check_text(ld, c) != 0) {
      return -1;
    }
    if (c->type != XML_ELEMENT_NODE || is_named(c, "wall") || is_named(c, "obstacle")) {
      continue;
    }
    int k = 0;
    while (k < ONCE && !is_named(c, once[k])) {
      k++;
    }
    if (k == ONCE) {
      nps_arena_errf(ld->err, ld->err_len, ld->path, line_of(c),
                     "unknown element <%s> in <arena> (expected polygon, walls, wall, copters, sonars, floor, obstacle)",
                     (const char *)c->name);
      return -1;
    }
    if (first[k]) {
      nps_arena_errf(ld->err, ld->err_len, ld->path, line_of(c), "<%s> is given twice (first at line %d)",
                     once[k], line_of(first[k]));
      return -1;
    }
    first[k] = c;
  }
  if (!first[0]) {
    nps_arena_errf(ld->err, ld->err_len, ld->path, line_of(root), "<arena> needs a <polygon>");
    return -1;
  }
  if (parse_polygon(ld, first[0]) != 0) {
    return -1;
  }
  nps_wall_params_default(&ld->defaults);
  if (first[1]) {
    ld->defaults.line = line_of(first[1]);
    if (parse_attrs(ld, first[1], &nps_arena_wall_table, &ld->defaults, NULL) != 0) {
      return -1;
    }
  }
  if ((first[2] && parse_attrs(ld, first[2], &nps_arena_copters_table, cfg, NULL) != 0) ||
      (first[3] && parse_attrs(ld, first[3], &nps_arena_sonars_table, cfg, NULL) != 0)) {
    return -1;
  }
  if ((first[4] && parse_floor(ld, first[4]) != 0) || parse_obstacles(ld, root) != 0) {
    return -1;
  }
  cfg->copters_line = first[2] ? line_of(first[2]) : 0;
  cfg->sonars_line = first[3] ? line_of(first[3]) : 0;
  int edges = cfg->num_points - 1;
  if (edges < 1) {
    return 0; /* nps_arena_config_check names the missing corners */
  }
  cfg->walls = calloc((size_t)edges, sizeof * cfg->walls);
  int *seen = calloc((size_t)edges, sizeof * seen);
  int rc = cfg->walls && seen ? 0 : -1;
  if (rc != 0) {
    nps_arena_errf(ld->err, ld->err_len, ld->path, line_of(root), "out of memory");
  }
  for (int i = 0; rc == 0 && i < edges; i++) {
    cfg->walls[i] = ld->defaults;
  }
  for (xmlNodePtr c = root->children; rc == 0 && c; c = c->next) {
    if (is_named(c, "wall")) {
      rc = parse_wall(ld, c, seen);
    }
  }
  free(seen);
  return rc;
}

static int parse_root(struct loader *ld, xmlNodePtr root)
{
  static const char *const name_only[] = { "name", NULL };
  struct nps_arena_config *cfg = ld->cfg;
  if (!root || !is_named(root, "arena")) {
    nps_arena_errf(ld->err, ld->err_len, ld->path, root ? line_of(root) : 0,
                   "expected <arena> as the root element, found <%s>", root ? (const char *)root->name : "");
    return -1;
  }
  cfg->line = line_of(root);
  if (parse_attrs(ld, root, &nps_arena_arena_table, cfg, name_only) != 0) {
    return -1;
  }
  char *name = attr(root, "name");
  if (name) {
    snprintf(cfg->name, sizeof cfg->name, "%s", name);
    xmlFree(name);
  }
  return parse_children(ld, root);
}

/** The first parser error (libxml2 reports several for one mistake; the first names it). */
struct first_error {
  int set;
  int line;
  char msg[256];
};

static void on_xml_error(void *ctx, xmlErrorPtr e)
{
  xmlParserCtxtPtr ctxt = ctx;
  struct first_error *f = ctxt ? ctxt->_private : NULL;
  if (!f || f->set || !e || e->level < XML_ERR_ERROR) {
    return;
  }
  f->set = 1;
  f->line = e->line;
  snprintf(f->msg, sizeof f->msg, "%s", e->message ? e->message : "unknown error");
  f->msg[strcspn(f->msg, "\n")] = '\0';
}

/** The whole file in a NUL-terminated buffer (caller frees), or NULL with errno. */
static char *read_file(const char *path, size_t *len)
{
  FILE *f = fopen(path, "rb");
  if (!f) {
    return NULL;
  }
  char *buf = NULL;
  size_t cap = 0, n = 0, got;
  do {
    if (cap - n < 4096) {
      cap = cap ? 2 * cap : 16384;
      char *p = realloc(buf, cap + 1);
      if (!p) {
        free(buf);
        fclose(f);
        errno = ENOMEM;
        return NULL;
      }
      buf = p;
    }
    got = fread(buf + n, 1, cap - n, f);
    n += got;
  } while (got > 0);
  int failed = ferror(f);
  int saved = errno;
  fclose(f);
  if (failed) {
    free(buf);
    errno = saved ? saved : EIO;
    return NULL;
  }
  buf[n] = '\0';
  *len = n;
  return buf;
}

int nps_arena_config_load(struct nps_arena_config *cfg, const char *path, char *err, size_t err_len)
{
  nps_arena_config_init(cfg, path);
  size_t len = 0;
  char *text = read_file(path, &len);
  if (!text) {
    nps_arena_errf(err, err_len, path, 0, "cannot read the arena file: %s", strerror(errno));
    return -1;
  }
  xmlParserCtxtPtr ctxt = xmlNewParserCtxt();
  if (!ctxt || len > INT_MAX) {
    nps_arena_errf(err, err_len, path, 0, ctxt ? "the arena file is too large" : "out of memory");
    xmlFreeParserCtxt(ctxt);
    free(text);
    return -1;
  }
  struct first_error first = { 0, 0, "" };
  ctxt->_private = &first;
  ctxt->sax->serror = on_xml_error;
  xmlDocPtr doc = xmlCtxtReadMemory(ctxt, text, (int)len, path, NULL, XML_PARSE_NONET);
  free(text);
  if (!doc || first.set) {
    nps_arena_errf(err, err_len, path, first.line, "malformed XML: %s", first.set ? first.msg : "no document");
    xmlFreeDoc(doc);
    xmlFreeParserCtxt(ctxt);
    return -1;
  }
  struct loader ld = { .cfg = cfg, .path = path, .err = err, .err_len = err_len };
  int rc = parse_root(&ld, xmlDocGetRootElement(doc));
  xmlFreeDoc(doc);
  xmlFreeParserCtxt(ctxt);
  if (rc == 0) {
    rc = nps_arena_config_check(cfg, err, err_len);
  }
  if (rc != 0) {
    nps_arena_config_free(cfg);
  }
  return rc;
}
