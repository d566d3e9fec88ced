<?xml version="1.0" encoding="UTF-8"?>
<tileset version="1.10" name="ext" tilewidth="24" tileheight="24" tilecount="2" columns="2">
 <tile id="0"><properties><property name="ntile" value="22DEGpnS"/><property name="material" type="int" value="2"/></properties></tile>
</tileset>
